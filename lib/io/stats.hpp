// Per-step statistics CSV (-stats FILE.csv), one row per step, flushed as written so an interrupted run keeps
// every completed row. Header (a contract; readers go by column name):
//   step,time,newton_its,ksp_its,wall_s,energy,min_alpha,max_disp,reason,linear_solves,ksp_at_limit,residual,
//   barrier_cells,barrier_fallback
// newton_its counts updates of the state by a line search, linear_solves the Newton systems solved (including the
// converging one, whose small step is applied as a final correction without counting as an update, where it does not
// raise |g|), ksp_at_limit those stopped by -ksp_max_it, residual |gradient|_2 over the free dofs at the end,
// barrier_cells the cells whose aberration barrier is active at the start of the step (0 < alpha < eps),
// barrier_fallback the cells evaluated with the mollifier during the step because their alpha was ~0 then (Sec. 7.1).
#pragma once

#include <petscsys.h>

#include <cstdio>
#include <string>

namespace aries::io {

struct StepStats {
  PetscInt step = 0;
  double time = 0.0;
  PetscInt newtonIterations = 0, linearIterations = 0;
  double wallSeconds = 0.0, energy = 0.0, minAlpha = 0.0, maxDisplacement = 0.0;
  std::string reason;
  PetscInt linearSolves = 0, linearAtLimit = 0;
  double residual = 0.0;
  PetscInt barrierCells = 0, barrierFallback = 0;
  PetscInt coarseNewton = 0, coarseLinear = 0;  // the nested iteration's coarse levels (-coarse_mesh)
  int coarseStart = -1;                         // -1 no nested start, 0 not taken, 1 taken
  PetscInt localIterations = 0;                 // -newton_local_solve's iterations (solver/local_solve.cpp)
};

class StatsWriter {
 public:
  ~StatsWriter();
  // Collective. With resumeAfterStep >= 0 (restart) the rows of later steps are dropped and new rows are appended.
  PetscErrorCode open(MPI_Comm comm, const std::string &path, PetscInt resumeAfterStep = -1);
  PetscErrorCode append(const StepStats &s);                    // rank 0 writes
  bool isOpen() const { return file_ != nullptr; }

 private:
  std::FILE *file_ = nullptr;
};

}  // namespace aries::io
