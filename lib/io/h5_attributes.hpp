// The aries version and git commit that every file aries writes carries (attributes aries_version, aries_commit on
// the root group); the attribute helpers themselves are core's (core/h5_attributes.hpp).
#pragma once

#include "core/h5_attributes.hpp"

namespace aries::io {

using core::readScalarAttribute;
using core::writeScalarAttribute;
using core::writeStringAttribute;

bool writeVersionAttributes(hid_t file);

}  // namespace aries::io
