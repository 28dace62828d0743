#include "io/h5_attributes.hpp"

#include "io/version.hpp"

namespace aries::io {

bool writeStringAttribute(hid_t object, const char *name, const std::string &value) {
  hid_t type = H5Tcopy(H5T_C_S1);
  H5Tset_size(type, value.size() + 1);
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  const bool ok = a >= 0 && H5Awrite(a, type, value.c_str()) >= 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  H5Tclose(type);
  return ok;
}

bool writeVersionAttributes(hid_t file) {
  return writeStringAttribute(file, "aries_version", version()) && writeStringAttribute(file, "aries_commit", gitCommit());
}

}  // namespace aries::io
