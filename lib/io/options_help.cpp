#include "io/options_help.hpp"

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
  PetscFunctionReturn(0);
}

}  // namespace aries::io
