#include "core/errors.hpp"

#include <cstdio>
#include <cstring>
#include <vector>

namespace aries::core {

namespace {
std::string gProgram = "aries";
bool gUserError = false;

bool isUserError(PetscErrorCode n) {
  return n == PETSC_ERR_USER_INPUT || n == PETSC_ERR_FILE_OPEN || n == PETSC_ERR_FILE_READ ||
         n == PETSC_ERR_FILE_UNEXPECTED || n == PETSC_ERR_FILE_WRITE;
}

PetscErrorCode handler(MPI_Comm comm, int line, const char *func, const char *file, PetscErrorCode n,
                       PetscErrorType p, const char *mess, void *ctx) {
  if (isUserError(n)) {
    if (p == PETSC_ERROR_INITIAL) {
      gUserError = true;
      PetscMPIInt rank = 0;
      MPI_Comm_rank(PETSC_COMM_WORLD, &rank);
      if (rank == 0) {
        std::fprintf(stderr, "%s: error: %s\n", gProgram.c_str(), mess ? mess : "unknown error");
        std::fflush(stderr);
      }
    }
    return n;
  }
  gUserError = false;
  return PetscTraceBackErrorHandler(comm, line, func, file, n, p, mess, ctx);
}
}  // namespace

PetscErrorCode installErrorHandler(const char *program) {
  PetscFunctionBeginUser;
  gProgram = program;
  PetscCall(PetscPushErrorHandler(handler, nullptr));
  PetscFunctionReturn(0);
}

bool lastErrorWasUserError() { return gUserError; }

int exitCodeFor(PetscErrorCode ierr) { return ierr == 0 ? 0 : (gUserError ? 1 : 2); }

PetscErrorCode collectiveCheck(MPI_Comm comm, bool bad, const std::string &message) {
  PetscMPIInt rank, size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscMPIInt mine = bad ? rank : size, first = size;
  PetscCallMPI(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm));
  if (first == size) PetscFunctionReturn(0);
  int len = (rank == first) ? static_cast<int>(message.size()) : 0;
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, first, comm));
  std::vector<char> buf(len + 1, '\0');
  if (rank == first) std::memcpy(buf.data(), message.data(), len);
  PetscCallMPI(MPI_Bcast(buf.data(), len, MPI_CHAR, first, comm));
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "%s", buf.data());
}

}  // namespace aries::core
