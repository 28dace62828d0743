#include "io/files.hpp"

#include <sstream>
#include <sys/stat.h>

namespace aries::io {

std::string directoryOf(const std::string &p) {
  const auto s = p.find_last_of('/');
  return s == std::string::npos ? "." : (s == 0 ? "/" : p.substr(0, s));
}

std::string fileNameOf(const std::string &p) {
  const auto s = p.find_last_of('/');
  return s == std::string::npos ? p : p.substr(s + 1);
}

bool makeDirectories(const std::string &dir) {
  std::string cur = (!dir.empty() && dir[0] == '/') ? "/" : "";
  std::istringstream parts(dir);
  std::string part;
  while (std::getline(parts, part, '/')) {
    if (part.empty()) continue;
    cur += part + "/";
    struct stat st;
    if (stat(cur.c_str(), &st) == 0) {
      if (!S_ISDIR(st.st_mode)) return false;
    } else if (mkdir(cur.c_str(), 0755) != 0) {
      return false;
    }
  }
  return true;
}

bool makeParentDirectory(const std::string &path) { return makeDirectories(directoryOf(path)); }

}  // namespace aries::io
