// `aries -help` and docs/options.md's tables, both rendered from the option declarations of every layer
// (core/option_decl.hpp; mesh/mesh_options.hpp, fem/fem_options.hpp, solver/solver_options.hpp, io/io_options.hpp), the energy registry
// (energies/registry.hpp: names, shapes, their own parameters) and the output fields (io/run_output.hpp).
// aries-options-doc writes the tables into docs/options.md between <!-- options:KEY --> markers, and ctest
// docs.options checks that the file in git is what it writes: a default in the docs cannot differ from the code's.
#pragma once

#include "core/option_decl.hpp"

#include <petscsys.h>

#include <string>
#include <vector>

namespace aries::io {

// The solver's sections in docs order (-help prints them in this order).
const std::vector<core::OptionSection> &optionSections();
// Registers them with the readers (core::registerOptionSections) so that reading an undeclared option is an error.
void registerOptionSections();

// Usage ("-newton_tol X") and default ("`1e-4` (static), `1e-2` (beuler)"; markdown when `markdown`) of a declaration.
std::string optionUsage(const core::OptionDecl &d);
std::string optionDefault(const core::OptionDecl &d, bool markdown);

// Plain text of a section for a -help listing: one usage line with its default, the help wrapped below it.
std::string sectionHelpText(const core::OptionSection &s, int width = 110);
// The energies of the registry with their shapes, definitions and own parameters, for a -help listing.
std::string energiesHelpText(int width = 110);
// Markdown tables: a section's options; the energies (name | shapes | definition); the energies' own parameters;
// the output fields. `key` is a section key, or "energies", "energy_parameters", "output_fields".
std::string markdownTable(const std::string &key, const std::vector<core::OptionSection> &extra = {});
// Every generated block's key (the sections', then the registry's and the fields').
std::vector<std::string> markdownKeys(const std::vector<core::OptionSection> &extra = {});

PetscErrorCode printOptionsHelp(MPI_Comm comm, int width = 110);

}  // namespace aries::io
