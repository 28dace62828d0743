// The aries version (CMake project version) and the git commit of the source tree it was built from ("-dirty" when
// the tree had uncommitted changes, "unknown" outside a git checkout). Printed by -version and in the run banner,
// and stored in the output .h5 files and the stats CSV header, so every result names the code that made it.
#pragma once

namespace aries::io {

const char *version();
const char *gitCommit();

}  // namespace aries::io
