// When a Newton system reuses the preconditioner built for an earlier one (-multigrid_reuse_growth; CG + GAMG by the
// preconditioner rule, NewtonSolver::choosePreconditioner). A GAMG hierarchy costs more than a solve with it (the
// Galerkin products; docs/peer.md's `gamg` and `gamg_rebuild` rows), and the Hessians of one load step differ little
// where the hierarchy matters: its coarse spaces come from the rest shape's rigid modes. So a hierarchy is kept
// while the solves with it stay within `growth` times the Krylov iterations of its first solve. A solve with a kept
// hierarchy that reaches that many iterations is stopped there (ConvergenceCheck::linearTest, as a failed
// preconditioner) and, like any solve that fails with a kept hierarchy, solved again at once with a new one
// (NewtonContext::finishSystem): a stale hierarchy costs at most `growth` times a good one's solve. (Without the stop,
// a load sub-step of the 1M-tet peer box's `before` run spent 5222 iterations in one solve with the hierarchy of the
// sub-step before, which solved its own systems in about 100.) A hierarchy also serves at most kMaxSystems systems:
// one built on a crushed start stays within `growth` of its first solve while Newton converges, but a new one at the
// converging state solves in a quarter of the iterations (that run's last sub-step with the hierarchy built every
// second system, aries' rule before: 98 at its start, 25 at its end; with one kept for all its 12 systems: about 100
// each).
#pragma once

#include <algorithm>

namespace aries::solver {

class PreconditionerReuse {
 public:
  // The first solve of a hierarchy counts at least this many iterations (a hierarchy that solved its first system in 3
  // is not judged stale at 5).
  static constexpr long kMinReference = 10;
  // Newton systems one hierarchy serves at most (the peer box's lifted solve and its two Newton systems).
  static constexpr int kMaxSystems = 3;

  // growth <= 0: never reuse (every Newton system builds its preconditioner, PETSc's default).
  void enable(double growth) { growth_ = growth; }
  bool enabled() const { return growth_ > 0.0; }
  // Would the next Newton system build its preconditioner?
  bool rebuildNext() const {
    return !enabled() || reference_ < 0 || lastFailed_ || systems_ >= kMaxSystems ||
           static_cast<double>(last_) > allowedIterations();
  }
  // A Newton system is about to be solved: true where it builds its preconditioner (force: whatever the rule says).
  bool beginSystem(bool force = false) {
    building_ = force || rebuildNext();
    systems_ = building_ ? 1 : systems_ + 1;
    inSystem_ = true;
    return building_;
  }
  // Its solve ended after `iterations` Krylov iterations, converged or not.
  void endSystem(long iterations, bool converged) {
    if (building_) reference_ = converged ? iterations : -1;  // a failed first solve is no reference: build again
    last_ = iterations;
    lastFailed_ = !converged;
    inSystem_ = false;
  }
  // The Krylov iterations at which the solve in progress gives up on a kept hierarchy (-1: no such limit: the rule is
  // off, the system built its own, or no Newton system is being solved).
  long iterationLimit() const {
    if (!enabled() || building_ || !inSystem_) return -1;
    return static_cast<long>(allowedIterations());
  }
  // Did the system in progress (or the last one) build its preconditioner?
  bool built() const { return building_; }

 private:
  // A solve with the kept hierarchy may take this many Krylov iterations: growth x its first solve's (10 at least).
  double allowedIterations() const {
    return growth_ * static_cast<double>(std::max(reference_, kMinReference));
  }
  double growth_ = 0.0;
  long reference_ = -1;  // the Krylov iterations of the kept hierarchy's first solve (-1: none kept)
  long last_ = 0;        // the last solve's
  bool lastFailed_ = false;
  bool building_ = true;
  bool inSystem_ = false;  // between beginSystem and endSystem
  int systems_ = 0;        // the systems the current hierarchy has served
};

}  // namespace aries::solver
