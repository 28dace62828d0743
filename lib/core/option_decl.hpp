// One declaration per option: its name, value type, default, bounds and a one- or two-sentence help. The readers
// (core/options.hpp: get), `aries -help`, the unused-option check and docs/options.md's tables
// (aries-options-doc, ctest docs.options) all come from these declarations, so the documented default is the
// code's default by construction: a default is a string parsed by the same reader as a user's value.
//
// Declared per layer in <layer>/<layer>_options.hpp as constexpr values, grouped into sections (a docs heading and
// its table); the sections of every layer are listed once in io/options_help.cpp. Pure C++: no PETSc.
#pragma once

#include <limits>

namespace aries::core {

enum class OptionType {
  Flag,    // on/off: `-x`, `-x true|false`
  Int,     // one integer
  Real,    // one finite real
  Choice,  // one word of `args` ("static|beuler"); read as its index
  Text,    // a word or a path
  Reals,   // comma-separated reals (`count` of them if >= 0, or `countAlt`)
  Words,   // comma-separated words
};

struct OptionDecl {
  const char *name = "";  // "-newton_tol"; for a family (see `family`) the suffix: "-translate"
  const char *args = "";  // the value's shape in usage lines: "X", "x,y,z", the choices "static|beuler"
  OptionType type = OptionType::Real;
  const char *help = "";  // one or two sentences
  // The default: up to two cases (`when` names the case, e.g. the integrator; nullptr = every case), each a
  // string the reader parses exactly as a user's value. `computed` describes a default the code derives when no
  // case applies (or nullptr: no default, the option is absent).
  const char *value = nullptr, *when = nullptr;
  const char *value2 = nullptr, *when2 = nullptr;
  const char *computed = nullptr;
  // Validation of numbers (Int, Real, each entry of Reals): lo <= x <= hi, strict where `loOpen` / `hiOpen`.
  double lo = -std::numeric_limits<double>::infinity(), hi = std::numeric_limits<double>::infinity();
  bool loOpen = false, hiOpen = false;
  int count = -1, countAlt = -1;  // Reals: the number of entries (-1: any)
  const char *family = nullptr;   // a family read under a run-time prefix: its docs name, e.g. "-bc_clamp_<id>_"

  // Builders (each returns a modified copy, so declarations read as one expression).
  constexpr OptionDecl byDefault(const char *v) const { OptionDecl d = *this; d.value = v; return d; }
  constexpr OptionDecl byDefault(const char *v, const char *w, const char *v2, const char *w2) const {
    OptionDecl d = *this; d.value = v; d.when = w; d.value2 = v2; d.when2 = w2; return d;
  }
  constexpr OptionDecl otherwise(const char *text) const { OptionDecl d = *this; d.computed = text; return d; }
  constexpr OptionDecl atLeast(double x) const { OptionDecl d = *this; d.lo = x; d.loOpen = false; return d; }
  constexpr OptionDecl above(double x) const { OptionDecl d = *this; d.lo = x; d.loOpen = true; return d; }
  constexpr OptionDecl atMost(double x) const { OptionDecl d = *this; d.hi = x; d.hiOpen = false; return d; }
  constexpr OptionDecl below(double x) const { OptionDecl d = *this; d.hi = x; d.hiOpen = true; return d; }
  constexpr OptionDecl entries(int n, int alt = -1) const { OptionDecl d = *this; d.count = n; d.countAlt = alt; return d; }
  constexpr OptionDecl inFamily(const char *f) const { OptionDecl d = *this; d.family = f; return d; }
};

constexpr OptionDecl declare(OptionType type, const char *name, const char *args, const char *help) {
  OptionDecl d;
  d.name = name;
  d.args = args;
  d.type = type;
  d.help = help;
  return d;
}
constexpr OptionDecl flagOption(const char *name, const char *help) { return declare(OptionType::Flag, name, "", help); }
constexpr OptionDecl intOption(const char *name, const char *args, const char *help) {
  return declare(OptionType::Int, name, args, help);
}
constexpr OptionDecl realOption(const char *name, const char *args, const char *help) {
  return declare(OptionType::Real, name, args, help);
}
constexpr OptionDecl choiceOption(const char *name, const char *choices, const char *help) {
  return declare(OptionType::Choice, name, choices, help);
}
constexpr OptionDecl textOption(const char *name, const char *args, const char *help) {
  return declare(OptionType::Text, name, args, help);
}
constexpr OptionDecl realsOption(const char *name, const char *args, const char *help) {
  return declare(OptionType::Reals, name, args, help);
}
constexpr OptionDecl wordsOption(const char *name, const char *args, const char *help) {
  return declare(OptionType::Words, name, args, help);
}

// A docs section: `key` names its generated block in docs/options.md (<!-- options:KEY -->), `title` is the heading
// `-help` prints.
struct OptionSection {
  const char *key;
  const char *title;
  const OptionDecl *const *options;
  int count;
};

template <int N>
constexpr OptionSection section(const char *key, const char *title, const OptionDecl *const (&options)[N]) {
  return OptionSection{key, title, options, N};
}

}  // namespace aries::core
