// The convergence rule of projected Newton, tested on the Newton direction before any line search (paper Sec. 6).
// Pure C++ (no PETSc), so the decision itself is unit-tested (tests/kernels/test_convergence_rule.cpp); the solver
// (newton_iteration.cpp, certify) measures its inputs.
#pragma once

#include <cmath>

namespace aries::solver {

// How a Newton solve ended, beyond PETSc's SNESConvergedReason.
enum class Convergence {
  None,            // not converged (see the SNES reason)
  Initial,         // the first Newton step was already below the tolerance (applied as a final correction)
  NewtonStep,      // the Newton step after >= 1 update is below the tolerance (applied as a final correction)
  StepBound,       // backward Euler: the residual bounds the Newton step below the tolerance (no linear solve)
  EnergyRoundoff,  // the predicted decrease is below the energy's round-off and the step is short (applied as a
                   // final correction where it lowers |g|)
  Petsc,           // one of PETSc's tests the user enabled (-snes_atol, -snes_rtol, -snes_stol)
};

// A direction whose predicted decrease is below the energy's round-off certifies convergence only when its step is
// also at most this many times the tolerance: a long direction with no measurable decrease is a soft mode of the
// filtered Hessian (or an over-estimated round-off), not a certificate of equilibrium: it is an ordinary update (taken
// in full where it lowers |g|, through the line search otherwise; docs/options.md, "Newton").
constexpr double kRoundoffStepFactor = 10.0;

// Round-off of the summed energy: machine epsilon times the sum of the magnitudes of its terms, with a safety factor
// for the accumulation over many terms.
constexpr double kRoundoffSafety = 1e3;

struct DirectionMeasures {
  bool linearConverged = false;  // the linear solve that gave the direction solved the system (not truncated)
  int iteration = 0;             // Newton iteration (0: the step's initial state)
  double stepInf = 0.0;          // |p|_inf
  double stepTol = 0.0;          // -newton_tol * L (* dt); in the dynamic shape stage at least its own X L
  double slope = 0.0;            // g . p, the predicted decrease of the linear model
  double roundoff = 0.0;         // round-off of the summed energy (1e3 eps x the sum of its terms' magnitudes)
};

inline Convergence classifyDirection(const DirectionMeasures &m) {
  if (!m.linearConverged) return Convergence::None;
  if (m.stepInf <= m.stepTol) return m.iteration == 0 ? Convergence::Initial : Convergence::NewtonStep;
  if (std::abs(m.slope) <= m.roundoff && m.stepInf <= kRoundoffStepFactor * m.stepTol) return Convergence::EnergyRoundoff;
  return Convergence::None;
}

}  // namespace aries::solver
