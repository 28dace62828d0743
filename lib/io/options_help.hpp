// `aries -help`: every aries option with its default and meaning, from the option tables of docs/options.md (the
// table is generated from the docs at build time by cmake/options_help.py, so the help and the docs cannot
// disagree; e2e.help checks that the code reads no option the docs do not list).
#pragma once

#include <petscsys.h>

namespace aries::io {

struct OptionHelp {
  const char *section;  // the docs heading the option is listed under
  const char *usage;    // e.g. "-newton_tol X"
  const char *defaults;
  const char *meaning;
};

extern const OptionHelp kOptionHelp[];
extern const int kOptionHelpCount;

// Prints the table grouped by section, each meaning wrapped to `width` columns.
PetscErrorCode printOptionsHelp(MPI_Comm comm, int width = 110);

}  // namespace aries::io
