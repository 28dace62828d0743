#include "io/stats.hpp"

#include "core/errors.hpp"
#include "io/files.hpp"
#include "io/version.hpp"

#include <cctype>
#include <fstream>
#include <vector>

namespace aries::io {

StatsWriter::~StatsWriter() {
  if (file_) std::fclose(file_);
}

PetscErrorCode StatsWriter::open(MPI_Comm comm, const std::string &path, PetscInt resumeAfterStep) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  bool bad = false;
  if (rank == 0) {
    static const char header[] = "step,time,newton_its,ksp_its,wall_s,energy,min_alpha,max_disp,reason,linear_solves,ksp_at_limit,residual,barrier_cells,barrier_fallback,coarse_newton_its,coarse_ksp_its,coarse_start,local_its";
    std::vector<std::string> builds, keep;
    if (resumeAfterStep >= 0) {  // keep the rows up to the restart step, and the builds that wrote them, in a new file
      std::ifstream in(path);
      std::string line;
      while (std::getline(in, line))
        if (line.rfind("# aries ", 0) == 0)
          builds.push_back(line);
        else if (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])) && std::stol(line) <= resumeAfterStep)
          keep.push_back(line);
    }
    const std::string tmp = path + ".tmp";
    std::FILE *f = makeParentDirectory(path) ? std::fopen(tmp.c_str(), "w") : nullptr;
    if (f) {
      for (const auto &b : builds) std::fprintf(f, "%s\n", b.c_str());
      const std::string from = resumeAfterStep >= 0 ? " from step " + std::to_string(resumeAfterStep + 1) : "";
      std::fprintf(f, "# aries %s (git %s)%s\n%s\n", version(), gitCommit(), from.c_str(), header);
      for (const auto &l : keep) std::fprintf(f, "%s\n", l.c_str());
      bad = std::fclose(f) != 0 || std::rename(tmp.c_str(), path.c_str()) != 0;
      file_ = bad ? nullptr : std::fopen(path.c_str(), "a");
    }
    bad = bad || !file_;
  }
  PetscCall(core::collectiveCheck(comm, bad, "cannot open stats file '" + path + "' for writing (-stats)"));
  PetscFunctionReturn(0);
}

PetscErrorCode StatsWriter::append(const StepStats &s) {
  PetscFunctionBeginUser;
  if (file_) {
    std::fprintf(file_, "%d,%.10g,%d,%d,%.6f,%.17g,%.6e,%.10g,%s,%d,%d,%.6e,%d,%d,%d,%d,%d,%d\n", (int)s.step, s.time,
                 (int)s.newtonIterations, (int)s.linearIterations, s.wallSeconds, s.energy, s.minAlpha,
                 s.maxDisplacement, s.reason.c_str(), (int)s.linearSolves, (int)s.linearAtLimit, s.residual,
                 (int)s.barrierCells, (int)s.barrierFallback, (int)s.coarseNewton, (int)s.coarseLinear,
                 s.coarseStart, (int)s.localIterations);
    std::fflush(file_);
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::io
