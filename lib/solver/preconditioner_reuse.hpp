// When a Newton system reuses the preconditioner built for an earlier one (-multigrid_reuse_growth; CG + GAMG by the
// preconditioner rule, NewtonSolver::choosePreconditioner). A GAMG hierarchy costs more than a solve with it (the
// Galerkin products; docs/peer.md's `gamg` and `gamg_rebuild` rows), and the Hessians of one load step differ little
// where the hierarchy matters: its coarse spaces come from the rest shape's rigid modes. So a hierarchy is kept
// while the solves with it stay within `growth` times the Krylov iterations of its first solve, and built again after
// a solve that exceeded that or failed. The rule looks back one solve: the system after a slow one builds anew (a
// failed solve with a kept hierarchy is also solved again at once with a new one: NewtonContext::finishSystem).
#pragma once

#include <algorithm>

namespace aries::solver {

class PreconditionerReuse {
 public:
  // The first solve of a hierarchy counts at least this many iterations (a hierarchy that solved its first system in 3
  // is not judged stale at 5).
  static constexpr long kMinReference = 10;

  // growth <= 0: never reuse (every Newton system builds its preconditioner, PETSc's default).
  void enable(double growth) { growth_ = growth; }
  bool enabled() const { return growth_ > 0.0; }
  // Would the next Newton system build its preconditioner?
  bool rebuildNext() const {
    return !enabled() || reference_ < 0 || lastFailed_ ||
           static_cast<double>(last_) > growth_ * static_cast<double>(std::max(reference_, kMinReference));
  }
  // A Newton system is about to be solved: true where it builds its preconditioner (force: whatever the rule says).
  bool beginSystem(bool force = false) {
    building_ = force || rebuildNext();
    return building_;
  }
  // Its solve ended after `iterations` Krylov iterations, converged or not.
  void endSystem(long iterations, bool converged) {
    if (building_) reference_ = converged ? iterations : -1;  // a failed first solve is no reference: build again
    last_ = iterations;
    lastFailed_ = !converged;
  }
  // Did the system in progress (or the last one) build its preconditioner?
  bool built() const { return building_; }

 private:
  double growth_ = 0.0;
  long reference_ = -1;  // the Krylov iterations of the kept hierarchy's first solve (-1: none kept)
  long last_ = 0;        // the last solve's
  bool lastFailed_ = false;
  bool building_ = true;
};

}  // namespace aries::solver
