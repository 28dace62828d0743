#include "io/h5_attributes.hpp"

#include "io/version.hpp"

namespace aries::io {

bool writeVersionAttributes(hid_t file) {
  return writeStringAttribute(file, "aries_version", version()) && writeStringAttribute(file, "aries_commit", gitCommit());
}

}  // namespace aries::io
