// Strict readers for PETSc options. PETSc's own getters accept "1e4x" or report "Input string x has no numeric
// value" without naming the option; these name the option and say what is expected, raising PETSC_ERR_USER_INPUT
// (printed as one line by the aries error handler, lib/io/errors.hpp). All are collective-safe: every rank sees the
// same options database and raises the same error.
#pragma once

#include "core/option_decl.hpp"

#include <petscsys.h>

#include <string>
#include <vector>

namespace aries::core {

// Full option name for messages: "-" + prefix + name without its leading dash.
std::string optionName(const char *prefix, const char *name);

PetscErrorCode optionString(const char *prefix, const char *name, std::string *value, PetscBool *set);
PetscErrorCode optionReal(const char *prefix, const char *name, PetscReal *value, PetscBool *set);
// Comma-separated reals; `count` (if >= 0) demands exactly that many values, `countAlt` an alternative count.
PetscErrorCode optionRealList(const char *prefix, const char *name, std::vector<PetscReal> *values, PetscBool *set,
                              int count = -1, int countAlt = -1);

// Parses a finite real number; false if `text` is not one entirely.
bool parseReal(const std::string &text, double *value);
// Parses a whole number (written as any real: "3", "3.0", "3e0") that a PetscInt holds; false otherwise.
bool parseInteger(const std::string &text, PetscInt *value);

// Reading a declared option (core/option_decl.hpp). `prefix` reads it under a prefix (a region's material
// "region_2_", a clamp set's "bc_clamp_top_"); `when` names the case that picks the default ("static", "beuler").
// Unset, *value takes the declared default for `when`; where none applies (a computed default) it is left as it
// is. Values and defaults go through the same parser and the declared bounds.
struct ReadContext {
  const char *prefix = nullptr;
  const char *when = nullptr;
  bool inherit = false;  // unset keeps *value (a region's material starts from the global one): no default
};
PetscErrorCode get(const OptionDecl &d, PetscReal *value, PetscBool *set = nullptr, ReadContext at = {});
PetscErrorCode get(const OptionDecl &d, PetscInt *value, PetscBool *set = nullptr, ReadContext at = {});
PetscErrorCode get(const OptionDecl &d, PetscBool *value, PetscBool *set = nullptr, ReadContext at = {});
PetscErrorCode get(const OptionDecl &d, std::string *value, PetscBool *set = nullptr, ReadContext at = {});
PetscErrorCode get(const OptionDecl &d, std::vector<PetscReal> *value, PetscBool *set = nullptr, ReadContext at = {});
PetscErrorCode get(const OptionDecl &d, std::vector<std::string> *value, PetscBool *set = nullptr,
                   ReadContext at = {});
// The declared default for `when` without reading the option (it stays unused); *value unchanged if none applies.
PetscErrorCode getDefault(const OptionDecl &d, PetscReal *value, const char *when = nullptr);
// A Choice: *index is the position of the value among the declared choices ("static|beuler": 0 or 1).
PetscErrorCode getChoice(const OptionDecl &d, int *index, PetscBool *set = nullptr, ReadContext at = {});
template <class Enum>
PetscErrorCode getChoice(const OptionDecl &d, Enum *value, PetscBool *set = nullptr, ReadContext at = {}) {
  int index = static_cast<int>(*value);
  PetscFunctionBeginUser;
  PetscCall(getChoice(d, &index, set, at));
  *value = static_cast<Enum>(index);
  PetscFunctionReturn(0);
}

// Every section of every layer (io/options_help.cpp registers them at start-up): reading an option that no
// section declares is then an internal error, so nothing can be read without being documented.
void registerOptionSections(const OptionSection *sections, int count);
// The declared option closest to `name` (an unused option: a misspelling?) within two edits, or "".
std::string nearestDeclared(const std::string &name);
// The declared bounds as users read them: "> 0", ">= 1", "in [0, 0.5)", "in 0..7"; "" without bounds.
std::string boundsRule(const OptionDecl &d);
// The declared name as the user types it: "-newton_tol", or for a family "-bc_clamp_<id>_translate".
std::string declaredName(const OptionDecl &d);
// The words of a Choice's `args` ("static|beuler" -> {"static", "beuler"}).
std::vector<std::string> choices(const OptionDecl &d);
// Checks a declaration: every default parses as a value of its type within its bounds. "" when fine.
std::string checkDeclaration(const OptionDecl &d);

}  // namespace aries::core

namespace aries::core {
// Raises PETSC_ERR_USER_INPUT naming the first option nobody read (a typo or an option that does not apply).
PetscErrorCode rejectUnusedOptions();
}  // namespace aries::core
