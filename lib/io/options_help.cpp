#include "io/options_help.hpp"

#include "core/options.hpp"
#include "energies/registry.hpp"
#include "fem/fem_options.hpp"
#include "mesh/mesh_options.hpp"
#include "io/io_options.hpp"
#include "io/run_output.hpp"
#include "solver/solver_options.hpp"

#include <cstring>
#include <map>
#include <string>

namespace aries::io {

namespace {

// Greedy word wrap with a hanging indent.
std::string wrap(const std::string &text, const std::string &indent, int width) {
  std::string out, line = indent;
  std::size_t pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find(' ', pos);
    if (end == std::string::npos) end = text.size();
    const std::string word = text.substr(pos, end - pos);
    if (line.size() > indent.size() && static_cast<int>(line.size() + 1 + word.size()) > width) {
      out += line + "\n";
      line = indent;
    }
    line += (line.size() > indent.size() ? " " : "") + word;
    pos = end + 1;
  }
  if (line.size() > indent.size()) out += line + "\n";
  return out;
}

// A markdown table cell: '|' escaped.
std::string cell(const std::string &text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string code(const std::string &text, bool markdown) { return markdown ? "`" + text + "`" : text; }

// A default value as users read it: flags on/off.
std::string shownValue(const core::OptionDecl &d, const char *value) {
  if (d.type == core::OptionType::Flag) return std::strcmp(value, "true") == 0 ? "on" : "off";
  return value;
}

std::string shapesOf(const energies::EnergyInfo &e) {
  std::string shapes;
  for (auto [on, tag] : {std::pair{e.tet, "tet"}, std::pair{e.planar, "planar"}, std::pair{e.cloth, "cloth"}})
    if (on) shapes += (shapes.empty() ? "" : ", ") + std::string(tag);
  return shapes;
}

std::string paramUsage(const energies::ParamSpec &p) {
  return std::string(p.option) + " X" + (p.option2 ? std::string(", ") + p.option2 + " X" : "");
}

const char *kTableHead = "| option | default | meaning |\n|---|---|---|\n";

}  // namespace

const std::vector<core::OptionSection> &optionSections() {
  using core::section;
  static const std::vector<core::OptionSection> sections = {
      section("mesh", "Mesh and parallel layout", fem::opt::kMeshOptions),
      section("material", "Material", fem::opt::kMaterialOptions),
      section("singularity", "Singularity treatment (energies with I4/I6 terms)", fem::opt::kSingularityOptions),
      section("boundary", "Boundary conditions", fem::opt::kBoundaryOptions),
      section("body_forces", "Body forces", fem::opt::kBodyForceOptions),
      section("loads", "Surface loads", fem::opt::kLoadOptions),
      section("stepping", "Time stepping and initial state", solver::opt::kSteppingOptions),
      section("nested", "Nested iteration (coarse levels)", solver::opt::kNestedOptions),
      section("newton", "Newton", solver::opt::kNewtonOptions),
      section("cloth", "Cloth and planar terms: bending, contact, orientation", fem::opt::kClothOptions),
      section("output", "Output", io::opt::kOutputOptions),
      section("checkpoint", "Checkpoint and restart", io::opt::kCheckpointOptions),
  };
  return sections;
}

void registerOptionSections() {
  const auto &s = optionSections();
  core::registerOptionSections(s.data(), static_cast<int>(s.size()));
}

std::string optionUsage(const core::OptionDecl &d) {
  return core::declaredName(d) + (d.args[0] ? std::string(" ") + d.args : std::string());
}

std::string optionDefault(const core::OptionDecl &d, bool markdown) {
  std::string out;
  if (d.value) {
    out = code(shownValue(d, d.value), markdown);
    if (d.when) out += std::string(" (") + d.when + ")";
  }
  if (d.value2) {
    out += ", " + code(shownValue(d, d.value2), markdown);
    out += d.when2 ? std::string(" (") + d.when2 + ")" : std::string(" otherwise");
  }
  if (d.computed) out += (out.empty() ? "" : "; otherwise ") + std::string(d.computed);
  const std::string rule = core::boundsRule(d);
  if (!rule.empty()) out += "; " + std::string(d.type == core::OptionType::Reals ? "each " : "") + rule;
  return out;
}

std::string sectionHelpText(const core::OptionSection &s, int width) {
  std::string out = std::string(s.title) + ":\n";
  for (int k = 0; k < s.count; ++k) {
    const core::OptionDecl &d = *s.options[k];
    const std::string def = optionDefault(d, false);
    out += "  " + optionUsage(d) + (def.empty() ? "" : " [" + def + "]") + "\n" + wrap(d.help, "      ", width);
  }
  return out;
}

std::vector<std::string> markdownKeys(const std::vector<core::OptionSection> &extra) {
  std::vector<std::string> keys;
  for (const auto &s : optionSections()) keys.push_back(s.key);
  for (const auto &s : extra) keys.push_back(s.key);
  for (const char *k : {"energies", "energy_parameters", "output_fields"}) keys.push_back(k);
  return keys;
}

std::string markdownTable(const std::string &key, const std::vector<core::OptionSection> &extra) {
  std::string out;
  if (key == "energies") {
    out = "| energy | shapes | definition (conventions in `docs/energies.md`) |\n|---|---|---|\n";
    for (const auto &e : energies::kEnergyRegistry)
      out += "| `" + std::string(e.name) + "` | " + shapesOf(e) + " | " + cell(e.summary) + " |\n";
    return out;
  }
  if (key == "energy_parameters") {  // one row per option, with the energies that declare it
    out = "| option | energies | meaning |\n|---|---|---|\n";
    std::vector<std::string> order;
    std::map<std::string, std::pair<std::string, std::string>> rows;
    for (const auto &e : energies::kEnergyRegistry)
      for (int k = 0; k < e.numParams; ++k) {
        const auto &p = e.params[k];
        const std::string usage = paramUsage(p);
        auto it = rows.find(usage);
        const std::string who = std::string("`") + e.name + "`" + (p.required ? " (required)" : "");
        if (it == rows.end()) {
          order.push_back(usage);
          rows[usage] = {who, p.help};
        } else {
          it->second.first += ", " + who;
        }
      }
    for (const auto &u : order) {
      std::string usage = "`" + u + "`";
      for (std::size_t at = usage.find(", "); at != std::string::npos; at = usage.find(", ", at + 3))
        usage.replace(at, 2, "`, `");
      out += "| " + usage + " | " + rows[u].first + " | " + cell(rows[u].second) + " |\n";
    }
    return out;
  }
  if (key == "output_fields") {
    out = "| field | on | components | meaning |\n|---|---|---|---|\n";
    for (const auto &f : outputFields())
      out += "| `" + std::string(f.name) + "` | " + (f.perCell() ? "cell" : "vertex") + " | " +
             std::to_string(f.components) + " | " + cell(f.help) + " |\n";
    return out;
  }
  std::vector<core::OptionSection> all = optionSections();
  all.insert(all.end(), extra.begin(), extra.end());
  for (const auto &s : all) {
    if (key != s.key) continue;
    out = kTableHead;
    for (int k = 0; k < s.count; ++k) {
      const core::OptionDecl &d = *s.options[k];
      out += "| " + cell("`" + optionUsage(d) + "`") + " | " + cell(optionDefault(d, true)) + " | " + cell(d.help) +
             " |\n";
    }
  }
  return out;
}

std::string energiesHelpText(int width) {
  std::string out = "Energies (-energy NAME; the registry, lib/energies/catalog/):\n";
  for (const auto &e : energies::kEnergyRegistry) {
    out += "  " + std::string(e.name) + " [" + shapesOf(e) + "]\n" + wrap(e.summary, "      ", width);
    for (int k = 0; k < e.numParams; ++k)
      out += wrap(paramUsage(e.params[k]) + ": " + e.params[k].help, "      ", width);
  }
  return out;
}

PetscErrorCode printOptionsHelp(MPI_Comm comm, int width) {
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "aries options ([default]; docs/options.md has the same tables and more):\n"));
  for (const auto &s : optionSections()) PetscCall(PetscPrintf(comm, "%s", sectionHelpText(s, width).c_str()));
  PetscCall(PetscPrintf(comm, "%s", energiesHelpText(width).c_str()));
  PetscCall(PetscPrintf(comm, "Output fields (-output_fields):\n"));
  for (const auto &f : outputFields())
    PetscCall(PetscPrintf(comm, "  %s [%s, %d components]\n%s", f.name, f.perCell() ? "cell" : "vertex", f.components,
                          wrap(f.help, "      ", width).c_str()));
  PetscFunctionReturn(0);
}

}  // namespace aries::io
