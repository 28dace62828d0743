// aries-options-doc: writes or checks the generated tables of docs/options.md from the option declarations.
//
//   aries-options-doc --check docs/options.md   exit 1, naming the first difference, if the file is not what --write
//                                               would make it (ctest docs.options)
//   aries-options-doc --write docs/options.md   rewrite the blocks between <!-- options:KEY --> and <!-- /options -->
//
// Every key (io::markdownKeys: the sections of every layer, aries-matpoint's, the energies, their parameters, the
// output fields) must have exactly one block, and every declaration must be sound (core::checkDeclaration: its
// defaults parse as its type within its bounds, its help fits in 300 characters, no name declared twice).
#include "core/options.hpp"
#include "io/options_help.hpp"
#include "matpoint_options.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>

using namespace aries;

namespace {

const char kOpen[] = "<!-- options:", kClose[] = "<!-- /options -->";

int fail(const std::string &message) {
  std::fprintf(stderr, "aries-options-doc: %s\n", message.c_str());
  return 1;
}

// Problems of the declarations themselves, one per line ("" when sound).
std::string checkDeclarations(const std::vector<core::OptionSection> &extra) {
  std::string problems;
  std::set<std::string> seen;
  auto check = [&](const core::OptionSection &s, bool own) {
    for (int k = 0; k < s.count; ++k) {
      const std::string p = core::checkDeclaration(*s.options[k]);
      if (!p.empty()) problems += p + "\n";
      const std::string name = core::declaredName(*s.options[k]);
      if (own && !seen.insert(name).second) problems += name + " is declared twice\n";
    }
  };
  for (const auto &s : io::optionSections()) check(s, true);
  for (const auto &s : extra) check(s, false);  // aries-matpoint is a program of its own
  return problems;
}

// The file with every block regenerated; "" and *error set if the markers are wrong.
std::string regenerate(const std::string &text, const std::vector<core::OptionSection> &extra, std::string *error) {
  const auto keys = io::markdownKeys(extra);
  std::map<std::string, int> count;
  std::string out;
  std::size_t pos = 0;
  while (true) {
    const std::size_t open = text.find(kOpen, pos);
    if (open == std::string::npos) break;
    const std::size_t keyEnd = text.find(" -->", open);
    const std::size_t close = text.find(kClose, open);
    if (keyEnd == std::string::npos || close == std::string::npos) {
      *error = "a block opened at byte " + std::to_string(open) + " is not closed by " + kClose;
      return "";
    }
    const std::string key = text.substr(open + sizeof(kOpen) - 1, keyEnd - open - (sizeof(kOpen) - 1));
    if (std::find(keys.begin(), keys.end(), key) == keys.end()) {
      *error = "unknown block key '" + key + "'";
      return "";
    }
    ++count[key];
    const std::size_t bodyStart = keyEnd + 4 + 1;  // past " -->\n"
    out += text.substr(pos, bodyStart - pos) + io::markdownTable(key, extra);
    out += kClose;
    pos = close + sizeof(kClose) - 1;
  }
  out += text.substr(pos);
  for (const auto &k : keys)
    if (count[k] != 1) {
      *error = "block '" + k + "' appears " + std::to_string(count[k]) + " times (needs exactly one)";
      return "";
    }
  return out;
}

}  // namespace

int main(int argc, char **argv) {
  if (argc != 3 || (std::string(argv[1]) != "--check" && std::string(argv[1]) != "--write"))
    return fail("usage: aries-options-doc --check|--write docs/options.md");
  const bool write = std::string(argv[1]) == "--write";
  const std::string path = argv[2];
  const std::vector<core::OptionSection> extra{matpoint::opt::kSection};
  const std::string problems = checkDeclarations(extra);
  if (!problems.empty()) return fail("unsound option declarations:\n" + problems);
  std::ifstream in(path);
  if (!in) return fail("cannot read '" + path + "'");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  std::string error;
  const std::string fresh = regenerate(text, extra, &error);
  if (!error.empty()) return fail(path + ": " + error);
  if (write) {
    if (fresh != text) std::ofstream(path) << fresh;
    return 0;
  }
  if (fresh == text) return 0;
  std::size_t at = 0;
  while (at < text.size() && at < fresh.size() && text[at] == fresh[at]) ++at;
  const std::size_t lineStart = text.rfind('\n', at == 0 ? 0 : at - 1);
  const std::size_t from = lineStart == std::string::npos ? 0 : lineStart + 1;
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(from), '\n'));
  auto lineOf = [&](const std::string &s) { return s.substr(from, s.find('\n', from) - from); };
  return fail(path + " line " + std::to_string(line) +
              " differs from the option declarations (a table is edited by hand, or a declaration changed):\n  docs: " +
              lineOf(text) + "\n  code: " + lineOf(fresh) + "\nrun: build/aries-options-doc --write " + path);
}
