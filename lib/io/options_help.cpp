#include "io/options_help.hpp"

#include "energies/registry.hpp"

#include <cstring>
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

}  // namespace

PetscErrorCode printOptionsHelp(MPI_Comm comm, int width) {
  PetscFunctionBeginUser;
  PetscCall(PetscPrintf(comm, "aries options (docs/options.md; [default]):\n"));
  const char *section = "";
  for (int i = 0; i < kOptionHelpCount; ++i) {
    const OptionHelp &o = kOptionHelp[i];
    if (std::strcmp(o.section, section) != 0) {
      section = o.section;
      PetscCall(PetscPrintf(comm, "%s:\n", section));
    }
    PetscCall(PetscPrintf(comm, "  %s [%s]\n%s", o.usage, o.defaults, wrap(o.meaning, "      ", width).c_str()));
  }
  PetscCall(PetscPrintf(comm, "Energies (-energy NAME; the registry, lib/energies/catalog/):\n"));
  for (const auto &e : energies::kEnergyRegistry) {
    std::string shapes;
    for (auto [on, tag] : {std::pair{e.tet, "tet"}, std::pair{e.planar, "planar"}, std::pair{e.cloth, "cloth"}})
      if (on) shapes += (shapes.empty() ? "" : ", ") + std::string(tag);
    PetscCall(PetscPrintf(comm, "  %s [%s]\n%s", e.name, shapes.c_str(), wrap(e.summary, "      ", width).c_str()));
    for (int k = 0; k < e.numParams; ++k) {
      const energies::ParamSpec &p = e.params[k];
      const std::string usage = std::string(p.option) + (p.option2 ? std::string(", ") + p.option2 : "");
      PetscCall(PetscPrintf(comm, "%s", wrap(usage + ": " + p.help, "      ", width).c_str()));
    }
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::io
