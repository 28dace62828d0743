// The Newton solver's options as plain data, one struct per strategy (newton_steps.hpp), read once
// (readNewtonOptions) from the declarations in solver_options.hpp before the solver is set up.
#pragma once

#include <petscsys.h>

namespace aries::solver {

enum class EigenFilterMode { Clamp, Abs, Adaptive, None };
enum class LiftMode { Auto, Always, Never };  // -lift_increments (lifted_increment.cpp)

// ConvergenceCheck: -newton_tol, -newton_forcing.
struct ConvergenceOptions {
  double tol = 1e-4;      // the step tolerance is tol * L (* dt for backward Euler)
  double forcing = 0.0;   // inexact Newton's relative residual (0: off)
};

// HessianFilter: -psd_projection, -psd_eigensystem, -psd_scope, -psd_adaptive_tol.
struct FilterOptions {
  EigenFilterMode mode = EigenFilterMode::Clamp;
  bool analyticEigensystem = true;
  bool wholeElement = false;  // -psd_scope element
  double adaptiveTol = 0.01;
  bool exactNearSolution = false;  // -newton_exact_hessian: the unfiltered Hessian after full-length updates
  bool exactStart = false;         // -newton_exact_start: a solve starts unfiltered after a definite one
};

// SubspaceStep: -newton_subspace, -newton_subspace_max, -newton_extrapolate.
struct SubspaceOptions {
  PetscInt size = 1;             // previous updates combined with the Newton direction (0: off)
  double maxCoefficient = 0.0;   // limit of the Newton direction's coefficient (0: none)
  PetscInt extrapolate = 0;      // doublings of a full step along negative exact curvature (0: off)
};

// RotationalUpdate: -newton_rotation.
struct RotationOptions {
  PetscInt doublings = -1;  // -1: off, else the number of angle doublings tried
};

// AlphaSafeguard: -alpha_min.
struct SafeguardOptions {
  double alphaMin = 1e-6;
};

// The local solve after a concentrated update (local_solve.cpp): -newton_local_solve.
struct LocalSolveOptions {
  PetscInt maxIterations = 0;  // 0: off
};

struct NewtonOptions {
  ConvergenceOptions convergence;
  FilterOptions filter;
  SubspaceOptions subspace;
  RotationOptions rotation;
  SafeguardOptions safeguard;
  LocalSolveOptions local;
  LiftMode lift = LiftMode::Auto;  // -lift_increments: a load increment enters the first linear solves
  bool inertiaGuess = false;       // -newton_inertia_guess (backward Euler)
  bool rigidNearNullspace = true;  // -near_nullspace rigid|none
  PetscInt multigridMinDofs = 200000;  // -multigrid_min_dofs: static solves this large use CG + GAMG (-1: never)
  double multigridReuseGrowth = 1.5;    // -multigrid_reuse_growth: GAMG kept across Newton systems (0: never)
  // Not an option: the run starts backward Euler from a scramble, invert or collapse state of a 3D solid with fiber
  // terms (set by Simulation::setup); the preconditioner rule then picks point-block Jacobi (NewtonSolver). (Such a
  // start, or one with a volume term, also defaults -newton_forcing to 0.01: opt::kDegenerateStartForcing.)
  bool fiberDegenerateStart = false;
};

// Reads the Newton options for a static (`dynamic` false) or backward-Euler run. `base` and `prefix`: the options of
// a solver for a phase of its own (the detached start, prefix "detached_") start from `base` and are overridden by
// the same options under the prefix (-detached_newton_tol, ...).
PetscErrorCode readNewtonOptions(bool dynamic, const NewtonOptions *base, const char *prefix, NewtonOptions *out);

}  // namespace aries::solver
