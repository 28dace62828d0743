// Strict readers for PETSc options. PETSc's own getters accept "1e4x" or report "Input string x has no numeric
// value" without naming the option; these name the option and say what is expected, raising PETSC_ERR_USER_INPUT
// (printed as one line by the aries error handler, lib/io/errors.hpp). All are collective-safe: every rank sees the
// same options database and raises the same error.
#pragma once

#include <petscsys.h>

#include <string>
#include <vector>

namespace aries::core {

// Full option name for messages: "-" + prefix + name without its leading dash.
std::string optionName(const char *prefix, const char *name);

PetscErrorCode optionString(const char *prefix, const char *name, std::string *value, PetscBool *set);
PetscErrorCode optionReal(const char *prefix, const char *name, PetscReal *value, PetscBool *set);
PetscErrorCode optionInt(const char *prefix, const char *name, PetscInt *value, PetscBool *set);
PetscErrorCode optionBool(const char *prefix, const char *name, PetscBool *value, PetscBool *set);
// Comma-separated reals; `count` (if >= 0) demands exactly that many values, `countAlt` an alternative count.
PetscErrorCode optionRealList(const char *prefix, const char *name, std::vector<PetscReal> *values, PetscBool *set,
                              int count = -1, int countAlt = -1);
// Comma-separated words (ids or names).
PetscErrorCode optionWordList(const char *prefix, const char *name, std::vector<std::string> *values, PetscBool *set);

// Parses a finite real number; false if `text` is not one entirely.
bool parseReal(const std::string &text, double *value);

}  // namespace aries::core

namespace aries::core {
// Raises PETSC_ERR_USER_INPUT naming the first option nobody read (a typo or an option that does not apply).
PetscErrorCode rejectUnusedOptions();
}  // namespace aries::core
