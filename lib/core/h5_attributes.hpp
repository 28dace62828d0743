// HDF5 attributes: scalar numeric and string attributes on a file, group or dataset (every aries HDF5 file: meshes,
// step files, checkpoints).
#pragma once

#include <hdf5.h>

#include <string>

namespace aries::core {

bool writeStringAttribute(hid_t object, const char *name, const std::string &value);
// False (value untouched) if the attribute is missing or unreadable.
bool readStringAttribute(hid_t object, const char *name, std::string *value);

// A scalar numeric attribute (type: the HDF5 memory type of T, e.g. H5T_NATIVE_DOUBLE).
template <class T>
bool writeScalarAttribute(hid_t object, const char *name, hid_t type, const T &value) {
  hid_t space = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(object, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
  const bool ok = a >= 0 && H5Awrite(a, type, &value) >= 0;
  if (a >= 0) H5Aclose(a);
  H5Sclose(space);
  return ok;
}

// False (value untouched) if the attribute is missing or unreadable.
template <class T>
bool readScalarAttribute(hid_t object, const char *name, hid_t type, T *value) {
  if (H5Aexists(object, name) <= 0) return false;
  hid_t a = H5Aopen(object, name, H5P_DEFAULT);
  const bool ok = a >= 0 && H5Aread(a, type, value) >= 0;
  if (a >= 0) H5Aclose(a);
  return ok;
}

}  // namespace aries::core
