#include "core/h5_attributes.hpp"

namespace aries::core {

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

bool readStringAttribute(hid_t object, const char *name, std::string *value) {
  if (H5Aexists(object, name) <= 0) return false;
  hid_t a = H5Aopen(object, name, H5P_DEFAULT);
  if (a < 0) return false;
  hid_t type = H5Aget_type(a);
  bool ok = H5Tget_class(type) == H5T_STRING;
  if (ok && H5Tis_variable_str(type) > 0) {  // as h5py and others write them
    hid_t memType = H5Tcopy(H5T_C_S1);
    H5Tset_size(memType, H5T_VARIABLE);
    H5Tset_cset(memType, H5Tget_cset(type));  // HDF5 converts no character sets (ASCII vs UTF-8)
    char *text = nullptr;
    ok = H5Aread(a, memType, &text) >= 0 && text;
    if (ok) *value = text;
    if (text) H5free_memory(text);
    H5Tclose(memType);
  } else if (ok) {
    std::string buf(H5Tget_size(type), '\0');
    ok = H5Aread(a, type, buf.data()) >= 0;
    if (ok) *value = buf.c_str();
  }
  H5Tclose(type);
  H5Aclose(a);
  return ok;
}

}  // namespace aries::core
