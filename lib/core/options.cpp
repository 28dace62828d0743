#include "core/options.hpp"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <algorithm>
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

bool parseInteger(const std::string &text, PetscInt *value) {
  double v;
  if (!parseReal(text, &v) || v != std::floor(v) || !(std::abs(v) <= static_cast<double>(PETSC_MAX_INT))) return false;
  *value = static_cast<PetscInt>(v);
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

// ---- declared options (core/option_decl.hpp) -------------------------------------------------------------------
namespace aries::core {

namespace {

const OptionSection *gSections = nullptr;
int gSectionCount = 0;

const char *typeName(OptionType t) {
  switch (t) {
    case OptionType::Flag: return "flag";
    case OptionType::Int: return "integer";
    case OptionType::Real: return "real";
    case OptionType::Choice: return "choice";
    case OptionType::Text: return "text";
    case OptionType::Reals: return "list of reals";
    case OptionType::Words: return "list of words";
  }
  return "?";
}

std::string number(double x) {
  char buf[64];
  std::snprintf(buf, sizeof(buf), "%g", x);
  return buf;
}

// "" when x is within the declared bounds, else "must be ... (got x)".
std::string boundsProblem(const OptionDecl &d, double x) {
  const bool below = std::isfinite(d.lo) && (d.loOpen ? !(x > d.lo) : !(x >= d.lo));
  const bool above = std::isfinite(d.hi) && (d.hiOpen ? !(x < d.hi) : !(x <= d.hi));
  if (!below && !above) return "";
  return "must be " + boundsRule(d) + " (got " + number(x) + ")";
}

// Parsers shared by the user's values and the declared defaults: "" on success, else what is wrong (the caller
// prefixes the option's name).
std::string parseFlag(const std::string &text, PetscBool *v) {
  if (text.empty() || text == "1" || text == "true" || text == "yes" || text == "on") *v = PETSC_TRUE;
  else if (text == "0" || text == "false" || text == "no" || text == "off") *v = PETSC_FALSE;
  else return ": '" + text + "' is not a boolean (true|false)";
  return "";
}

std::string parseInt(const OptionDecl &d, const std::string &text, PetscInt *v) {
  char *end = nullptr;
  errno = 0;
  const long x = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || end == text.c_str() || *end != '\0' || errno == ERANGE || x > PETSC_MAX_INT || x < PETSC_MIN_INT)
    return ": '" + text + "' is not an integer";
  const std::string bad = boundsProblem(d, static_cast<double>(x));
  if (!bad.empty()) return " " + bad;
  *v = static_cast<PetscInt>(x);
  return "";
}

std::string parseRealValue(const OptionDecl &d, const std::string &text, PetscReal *v) {
  double x;
  if (!parseReal(text, &x)) return ": '" + text + "' is not a finite number";
  const std::string bad = boundsProblem(d, x);
  if (!bad.empty()) return " " + bad;
  *v = x;
  return "";
}

std::string parseReals(const OptionDecl &d, const std::string &text, std::vector<PetscReal> *v) {
  std::vector<PetscReal> out;
  for (const auto &item : splitCommas(text)) {
    double x;
    if (!parseReal(item, &x)) return ": '" + item + "' is not a finite number (in '" + text + "')";
    const std::string bad = boundsProblem(d, x);
    if (!bad.empty()) return ": every entry " + bad;
    out.push_back(x);
  }
  const int n = static_cast<int>(out.size());
  if (d.count >= 0 && n != d.count && n != d.countAlt) {
    const std::string counts = std::to_string(d.count) + (d.countAlt >= 0 ? " or " + std::to_string(d.countAlt) : "");
    return " takes " + counts + " comma-separated numbers, got " + std::to_string(n) + " ('" + text + "')";
  }
  *v = out;
  return "";
}

std::string parseWords(const std::string &text, std::vector<std::string> *v) {
  auto items = splitCommas(text);
  for (const auto &it : items)
    if (it.empty()) return ": empty entry in '" + text + "'";
  *v = items;
  return "";
}

std::string parseChoice(const OptionDecl &d, const std::string &text, int *index) {
  const auto words = choices(d);
  for (size_t i = 0; i < words.size(); ++i)
    if (words[i] == text) {
      *index = static_cast<int>(i);
      return "";
    }
  return ": '" + text + "' is not " + d.args;
}

// The default that applies in `when`, or nullptr.
const char *defaultFor(const OptionDecl &d, const char *when) {
  auto matches = [&](const char *w) { return !w || (when && std::strcmp(w, when) == 0); };
  if (d.value && matches(d.when)) return d.value;
  if (d.value2 && matches(d.when2)) return d.value2;
  return nullptr;
}

bool isDeclared(const OptionDecl &d) {
  for (int s = 0; s < gSectionCount; ++s)
    for (int k = 0; k < gSections[s].count; ++k)
      if (gSections[s].options[k] == &d) return true;
  return false;
}

// The option's text: the user's (*fromUser) or the declared default for at.when; *found false if neither.
PetscErrorCode lookup(const OptionDecl &d, OptionType type, ReadContext at, std::string *text, bool *found,
                      PetscBool *fromUser) {
  PetscFunctionBeginUser;
  if (d.type != type)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_PLIB, "option %s is declared as a %s but read as a %s",
            declaredName(d).c_str(), typeName(d.type), typeName(type));
  if (gSectionCount > 0 && !isDeclared(d))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_PLIB, "option %s is read but listed in no options section (io/options_help.cpp)",
            declaredName(d).c_str());
  PetscBool has = PETSC_FALSE;
  // The full name, composed as PETSc composes prefix and name; a family without a suffix (name "-", e.g.
  // -load_traction_<set>) is its prefix alone.
  const std::string full = optionName(at.prefix, d.name);
  if (type == OptionType::Flag) {  // a flag may come without a value
    PetscCall(PetscOptionsHasName(nullptr, nullptr, full.c_str(), &has));
    if (has) {
      char buf[64] = "";
      PetscCall(PetscOptionsGetString(nullptr, nullptr, full.c_str(), buf, sizeof(buf), nullptr));
      *text = buf;
    }
  } else {
    PetscCall(optionString(nullptr, full.c_str(), text, &has));
  }
  *fromUser = has;
  *found = has;
  if (!has && !at.inherit) {
    const char *fallback = defaultFor(d, at.when);
    if (fallback) {
      *text = fallback;
      *found = true;
    }
  }
  PetscFunctionReturn(0);
}

// Raises the parse problem: a user's value is bad input, a bad default is a bug in the declaration.
PetscErrorCode raise(const OptionDecl &d, ReadContext at, PetscBool fromUser, const std::string &problem) {
  PetscFunctionBeginUser;
  if (problem.empty()) PetscFunctionReturn(0);
  if (!fromUser)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_PLIB, "the declared default of option %s%s", declaredName(d).c_str(),
            problem.c_str());
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s%s", optionName(at.prefix, d.name).c_str(),
          problem.c_str());
}

template <class T, class Parse>
PetscErrorCode read(const OptionDecl &d, OptionType type, T *value, PetscBool *set, ReadContext at, Parse &&parse) {
  std::string text;
  bool found = false;
  PetscBool fromUser = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(lookup(d, type, at, &text, &found, &fromUser));
  if (found) {
    T parsed = *value;
    PetscCall(raise(d, at, fromUser, parse(text, &parsed)));
    *value = parsed;
  }
  if (set) *set = fromUser;
  PetscFunctionReturn(0);
}

}  // namespace

void registerOptionSections(const OptionSection *sections, int count) {
  gSections = sections;
  gSectionCount = count;
}

std::string boundsRule(const OptionDecl &d) {
  const bool hasLo = std::isfinite(d.lo), hasHi = std::isfinite(d.hi);
  if (hasLo && hasHi) {
    if (d.type == OptionType::Int) return "in " + number(d.lo) + ".." + number(d.hi);
    return std::string("in ") + (d.loOpen ? "(" : "[") + number(d.lo) + ", " + number(d.hi) + (d.hiOpen ? ")" : "]");
  }
  if (hasLo) return std::string(d.loOpen ? "> " : ">= ") + number(d.lo);
  if (hasHi) return std::string(d.hiOpen ? "< " : "<= ") + number(d.hi);
  return "";
}

std::string nearestDeclared(const std::string &name) {
  auto distance = [](const std::string &a, const std::string &b) {  // Levenshtein
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
      size_t diag = row[0];
      row[0] = i;
      for (size_t j = 1; j <= b.size(); ++j) {
        const size_t up = row[j];
        row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
        diag = up;
      }
    }
    return row[b.size()];
  };
  std::string best;
  size_t bestDistance = 3;
  for (int s = 0; s < gSectionCount; ++s)
    for (int k = 0; k < gSections[s].count; ++k) {
      const OptionDecl &d = *gSections[s].options[k];
      if (d.family) continue;
      const size_t dist = distance(name, d.name);
      if (dist < bestDistance) {
        bestDistance = dist;
        best = d.name;
      }
    }
  return best;
}

std::string declaredName(const OptionDecl &d) {
  if (!d.family) return d.name;
  return std::string(d.family) + (d.name[0] == '-' ? d.name + 1 : d.name);
}

std::vector<std::string> choices(const OptionDecl &d) {
  std::vector<std::string> out;
  std::string item;
  std::istringstream in(d.args);
  while (std::getline(in, item, '|')) out.push_back(item);
  return out;
}

PetscErrorCode get(const OptionDecl &d, PetscReal *value, PetscBool *set, ReadContext at) {
  return read(d, OptionType::Real, value, set, at,
              [&](const std::string &t, PetscReal *v) { return parseRealValue(d, t, v); });
}
PetscErrorCode get(const OptionDecl &d, PetscInt *value, PetscBool *set, ReadContext at) {
  return read(d, OptionType::Int, value, set, at, [&](const std::string &t, PetscInt *v) { return parseInt(d, t, v); });
}
PetscErrorCode get(const OptionDecl &d, PetscBool *value, PetscBool *set, ReadContext at) {
  return read(d, OptionType::Flag, value, set, at, [](const std::string &t, PetscBool *v) { return parseFlag(t, v); });
}
PetscErrorCode get(const OptionDecl &d, std::string *value, PetscBool *set, ReadContext at) {
  return read(d, OptionType::Text, value, set, at, [](const std::string &t, std::string *v) {
    *v = t;
    return std::string();
  });
}
PetscErrorCode get(const OptionDecl &d, std::vector<PetscReal> *value, PetscBool *set, ReadContext at) {
  return read(d, OptionType::Reals, value, set, at,
              [&](const std::string &t, std::vector<PetscReal> *v) { return parseReals(d, t, v); });
}
PetscErrorCode get(const OptionDecl &d, std::vector<std::string> *value, PetscBool *set, ReadContext at) {
  return read(d, OptionType::Words, value, set, at,
              [](const std::string &t, std::vector<std::string> *v) { return parseWords(t, v); });
}
// Readers of options declared elsewhere (an energy descriptor's ParamSpec): the same parsers and messages as get().
PetscErrorCode optionReal(const char *prefix, const char *name, PetscReal *value, PetscBool *set) {
  std::string text;
  PetscBool has = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(optionString(prefix, name, &text, &has));
  if (has) {
    const std::string problem = parseRealValue(realOption(name, "X", ""), text, value);
    if (!problem.empty())
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s%s", optionName(prefix, name).c_str(), problem.c_str());
  }
  if (set) *set = has;
  PetscFunctionReturn(0);
}

PetscErrorCode optionRealList(const char *prefix, const char *name, std::vector<PetscReal> *values, PetscBool *set,
                              int count, int countAlt) {
  std::string text;
  PetscBool has = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(optionString(prefix, name, &text, &has));
  if (has) {
    const std::string problem = parseReals(realsOption(name, "", "").entries(count, countAlt), text, values);
    if (!problem.empty())
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s%s", optionName(prefix, name).c_str(), problem.c_str());
  }
  if (set) *set = has;
  PetscFunctionReturn(0);
}

PetscErrorCode getDefault(const OptionDecl &d, PetscReal *value, const char *when) {
  const char *fallback = defaultFor(d, when);
  PetscFunctionBeginUser;
  if (fallback) PetscCall(raise(d, {}, PETSC_FALSE, parseRealValue(d, fallback, value)));
  PetscFunctionReturn(0);
}
PetscErrorCode getChoice(const OptionDecl &d, int *index, PetscBool *set, ReadContext at) {
  return read(d, OptionType::Choice, index, set, at,
              [&](const std::string &t, int *v) { return parseChoice(d, t, v); });
}

std::string checkDeclaration(const OptionDecl &d) {
  std::string problem;
  for (const char *v : {d.value, d.value2}) {
    if (!v || !problem.empty()) continue;
    const std::string text = v;
    PetscBool b;
    PetscInt i;
    PetscReal r;
    int c;
    std::string s;
    std::vector<PetscReal> rs;
    std::vector<std::string> ws;
    switch (d.type) {
      case OptionType::Flag: problem = parseFlag(text, &b); break;
      case OptionType::Int: problem = parseInt(d, text, &i); break;
      case OptionType::Real: problem = parseRealValue(d, text, &r); break;
      case OptionType::Choice: problem = parseChoice(d, text, &c); break;
      case OptionType::Text: break;
      case OptionType::Reals: problem = parseReals(d, text, &rs); break;
      case OptionType::Words: problem = parseWords(text, &ws); break;
    }
  }
  if (!problem.empty()) return "the declared default of " + declaredName(d) + problem;
  if (std::string(d.help).size() > 300) return declaredName(d) + ": help over 300 characters";
  if (d.type == OptionType::Choice && choices(d).size() < 2) return declaredName(d) + ": a choice needs 2+ words";
  return "";
}

}  // namespace aries::core
