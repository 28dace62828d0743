// HDF5 attributes shared by the writers: a scalar string attribute, and the aries version and git commit that every
// file aries writes carries (attributes aries_version, aries_commit on the root group).
#pragma once

#include <hdf5.h>

#include <string>

namespace aries::io {

bool writeStringAttribute(hid_t object, const char *name, const std::string &value);
bool writeVersionAttributes(hid_t file);

}  // namespace aries::io
