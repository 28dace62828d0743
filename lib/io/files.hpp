// File-system helpers for the writers.
#pragma once

#include <string>

namespace aries::io {

// Creates every missing directory of `dir` (like mkdir -p); false on failure.
bool makeDirectories(const std::string &dir);
// Creates the directory that will hold `path`; false on failure.
bool makeParentDirectory(const std::string &path);
// "a/b/c.h5" -> "a/b" ("." if there is no directory part) and "c.h5".
std::string directoryOf(const std::string &path);
std::string fileNameOf(const std::string &path);

}  // namespace aries::io
