#include "io/stats.hpp"

#include "fem/errors.hpp"
#include "io/files.hpp"

namespace aries::io {

StatsWriter::~StatsWriter() {
  if (file_) std::fclose(file_);
}

PetscErrorCode StatsWriter::open(MPI_Comm comm, const std::string &path) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  bool bad = false;
  if (rank == 0) {
    file_ = makeParentDirectory(path) ? std::fopen(path.c_str(), "w") : nullptr;
    bad = !file_;
    if (file_) {
      std::fprintf(file_, "step,time,newton_its,ksp_its,wall_s,energy,min_alpha,max_disp,reason\n");
      std::fflush(file_);
    }
  }
  PetscCall(fem::collectiveCheck(comm, bad, "cannot open stats file '" + path + "' for writing (-stats)"));
  PetscFunctionReturn(0);
}

PetscErrorCode StatsWriter::append(const StepStats &s) {
  PetscFunctionBeginUser;
  if (file_) {
    std::fprintf(file_, "%d,%.10g,%d,%d,%.6f,%.17g,%.6e,%.10g,%s\n", (int)s.step, s.time, (int)s.newtonIterations,
                 (int)s.linearIterations, s.wallSeconds, s.energy, s.minAlpha, s.maxDisplacement, s.reason.c_str());
    std::fflush(file_);
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::io
