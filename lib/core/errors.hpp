// Error reporting for the aries programs.
//
// User mistakes (bad options, unreadable or malformed input files) are raised with SETERRQ(..., PETSC_ERR_USER_INPUT
// or PETSC_ERR_FILE_OPEN/READ/UNEXPECTED, "...") and come out as ONE line on stderr:
//     aries: error: option -nu: Poisson's ratio must be in [0, 0.5) (got 0.7)
// Such errors must be raised collectively (on every rank, with the same text): only rank 0 prints them. Use
// collectiveCheck() for conditions that only some ranks can see. Every other error keeps PETSc's traceback.
#pragma once

#include <petscsys.h>

#include <string>

namespace aries::core {

// Installs the handler; `program` prefixes the message ("aries", "aries-matpoint").
PetscErrorCode installErrorHandler(const char *program);

// True if the last error seen by the handler was a user-input/file error (exit cleanly, no MPI_Abort needed).
bool lastErrorWasUserError();

// Exit code for a failed run: 1 for user errors, 2 for internal errors.
int exitCodeFor(PetscErrorCode ierr);

// Collective: if `bad` on any rank, every rank raises PETSC_ERR_USER_INPUT with the message of the lowest such rank.
PetscErrorCode collectiveCheck(MPI_Comm comm, bool bad, const std::string &message);

}  // namespace aries::core
