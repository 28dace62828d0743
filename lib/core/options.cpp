#include "core/options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace aries::core {

std::string optionName(const char *prefix, const char *name) {
  std::string n = name[0] == '-' ? name + 1 : name;
  return "-" + std::string(prefix ? prefix : "") + n;
}

bool parseReal(const std::string &text, double *value) {
  if (text.empty()) return false;
  const char *s = text.c_str();
  char *end = nullptr;
  errno = 0;
  const double v = std::strtod(s, &end);
  if (end == s || *end != '\0' || errno == ERANGE || !std::isfinite(v)) return false;
  *value = v;
  return true;
}

PetscErrorCode optionString(const char *prefix, const char *name, std::string *value, PetscBool *set) {
  char buf[PETSC_MAX_PATH_LEN] = "";
  PetscBool has = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetString(nullptr, prefix, name, buf, sizeof(buf), &has));
  if (has) {
    if (!buf[0]) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s needs a value", optionName(prefix, name).c_str());
    *value = buf;
  }
  if (set) *set = has;
  PetscFunctionReturn(0);
}

PetscErrorCode optionReal(const char *prefix, const char *name, PetscReal *value, PetscBool *set) {
  std::string text;
  PetscBool has = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(optionString(prefix, name, &text, &has));
  if (has) {
    double v;
    if (!parseReal(text, &v))
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: '%s' is not a finite number",
              optionName(prefix, name).c_str(), text.c_str());
    *value = v;
  }
  if (set) *set = has;
  PetscFunctionReturn(0);
}

PetscErrorCode optionInt(const char *prefix, const char *name, PetscInt *value, PetscBool *set) {
  std::string text;
  PetscBool has = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(optionString(prefix, name, &text, &has));
  if (has) {
    char *end = nullptr;
    errno = 0;
    const long v = std::strtol(text.c_str(), &end, 10);
    if (end == text.c_str() || *end != '\0' || errno == ERANGE || v > PETSC_MAX_INT || v < PETSC_MIN_INT)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: '%s' is not an integer",
              optionName(prefix, name).c_str(), text.c_str());
    *value = static_cast<PetscInt>(v);
  }
  if (set) *set = has;
  PetscFunctionReturn(0);
}

PetscErrorCode optionBool(const char *prefix, const char *name, PetscBool *value, PetscBool *set) {
  PetscBool has = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsHasName(nullptr, prefix, name, &has));
  if (has) {
    std::string text;
    PetscBool hasValue = PETSC_FALSE;
    char buf[64] = "";
    PetscCall(PetscOptionsGetString(nullptr, prefix, name, buf, sizeof(buf), &hasValue));
    text = buf;
    if (text.empty() || text == "1" || text == "true" || text == "yes" || text == "on") *value = PETSC_TRUE;
    else if (text == "0" || text == "false" || text == "no" || text == "off") *value = PETSC_FALSE;
    else
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: '%s' is not a boolean (true|false)",
              optionName(prefix, name).c_str(), text.c_str());
  }
  if (set) *set = has;
  PetscFunctionReturn(0);
}

static std::vector<std::string> splitCommas(const std::string &text) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) {
    const auto b = item.find_first_not_of(" \t"), e = item.find_last_not_of(" \t");
    out.push_back(b == std::string::npos ? std::string() : item.substr(b, e - b + 1));
  }
  if (!text.empty() && text.back() == ',') out.emplace_back();
  return out;
}

PetscErrorCode optionRealList(const char *prefix, const char *name, std::vector<PetscReal> *values, PetscBool *set,
                              int count, int countAlt) {
  std::string text;
  PetscBool has = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(optionString(prefix, name, &text, &has));
  if (has) {
    std::vector<PetscReal> v;
    for (const auto &item : splitCommas(text)) {
      double x;
      if (!parseReal(item, &x))
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: '%s' is not a finite number (in '%s')",
                optionName(prefix, name).c_str(), item.c_str(), text.c_str());
      v.push_back(x);
    }
    const int n = static_cast<int>(v.size());
    if (count >= 0 && n != count && n != countAlt) {
      if (countAlt >= 0)
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s takes %d or %d comma-separated numbers, got %d ('%s')",
                optionName(prefix, name).c_str(), count, countAlt, n, text.c_str());
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s takes %d comma-separated numbers, got %d ('%s')",
              optionName(prefix, name).c_str(), count, n, text.c_str());
    }
    *values = v;
  }
  if (set) *set = has;
  PetscFunctionReturn(0);
}

PetscErrorCode optionWordList(const char *prefix, const char *name, std::vector<std::string> *values,
                              PetscBool *set) {
  std::string text;
  PetscBool has = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(optionString(prefix, name, &text, &has));
  if (has) {
    auto items = splitCommas(text);
    for (const auto &it : items)
      if (it.empty())
        SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: empty entry in '%s'",
                optionName(prefix, name).c_str(), text.c_str());
    *values = items;
  }
  if (set) *set = has;
  PetscFunctionReturn(0);
}

}  // namespace aries::core

namespace aries::core {
PetscErrorCode rejectUnusedOptions() {
  PetscInt n = 0;
  char **names = nullptr, **values = nullptr;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(nullptr, &n, &names, &values));
  std::string first, all;
  for (PetscInt i = 0; i < n; ++i) {
    if (!all.empty()) all += ", ";
    all += std::string("-") + names[i];
  }
  const PetscInt unused = n;
  PetscCall(PetscOptionsLeftRestore(nullptr, &n, &names, &values));  // zeroes n
  if (unused > 0)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "unknown or unused option%s %s (misspelled, or not used by this configuration; see docs/options.md)",
            unused > 1 ? "s" : "", all.c_str());
  PetscFunctionReturn(0);
}
}  // namespace aries::core
