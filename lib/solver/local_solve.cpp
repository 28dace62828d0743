// The local solve (-newton_local_solve K; nonlinear elimination, Cai and Keyes 2002): after a Newton update that
// moved a few vertices far more than the rest of the body (cells snapping through at a rigid handle's rim, a scrambled
// body's last inverted cells), up to K Newton iterations on those vertices and their neighbours alone, the rest held.
// Only the cells that touch them are evaluated (fem::Discretization::setFocus), their system is a few thousand dofs
// solved by its own CG + Jacobi, and the safeguard and an Armijo backtracking guard each local update as they guard a
// global one (a full local step is doubled along negative curvature as a global one is, -newton_extrapolate). The
// global Newton solve then goes on from the relaxed state: it alone certifies convergence, so a step converges to the
// same tolerance with or without local solves (bench/results/interaction_local_solve_hex.md and
// degenerate_starts_local_solve.md measure what they save and cost).
#include "solver/local_vec.hpp"
#include "solver/newton.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace aries::solver {

namespace {
// An update is concentrated when the dofs that moved more than kMovingShare of its largest change carry at least
// kConcentration of its squared length and are at most kMaxDofShare of the free dofs.
constexpr double kMovingShare = 0.1;
constexpr double kConcentration = 0.6;
constexpr double kMaxDofShare = 0.05;
constexpr double kArmijo = 1e-4;  // sufficient decrease of a local update
constexpr int kMaxCuts = 30;      // backtracking halvings of a local update
constexpr PetscReal kLocalRtol = 1e-6;
constexpr PetscInt kLocalMaxIts = 2000;

// The local set's rows (the owned dofs marked in `mark`, which is made a 0/1 mask: LocalToGlobal summed each vertex's
// marks over the ranks that share it).
PetscErrorCode localRows(Vec mark, IS *is) {
  std::vector<PetscInt> rows;
  PetscInt lo, hi;
  PetscScalar *m;
  PetscFunctionBeginUser;
  PetscCall(VecGetOwnershipRange(mark, &lo, &hi));
  PetscCall(VecGetArray(mark, &m));
  for (PetscInt i = 0; i < hi - lo; ++i)
    if (m[i] != 0.0) {
      rows.push_back(lo + i);
      m[i] = 1.0;
    }
  PetscCall(VecRestoreArray(mark, &m));
  PetscCall(ISCreateGeneral(PetscObjectComm((PetscObject)mark), static_cast<PetscInt>(rows.size()), rows.data(),
                            PETSC_COPY_VALUES, is));
  PetscFunctionReturn(0);
}

// The focused potential (the set's cells, the other terms whole) and the alpha safeguard at trial states of one local
// solve.
struct LocalTrial {
  NewtonContext &ctx;
  const AlphaSafeguard &safeguard;
  std::vector<double> bandTop;  // each cell's singular band's top (Discretization::mollifierBandTop)
  double exactBelow = 0.0;      // the guard values' exactness bound for those bands (AlphaSafeguard::exactBelow)

  // The guard values at xg and, unless the safeguard rejects them against `ref` on some rank (*bad; collective; no
  // check without `ref`), the focused potential *e: a rejected trial needs no energy evaluation.
  PetscErrorCode evaluate(Vec xg, const std::vector<double> *ref, std::vector<double> *guard, PetscReal *e,
                          bool *bad) {
    LocalVec xl(ctx.disc->dm());
    int any = 0;
    PetscFunctionBeginUser;
    PetscCall(xl.fromGlobal(xg, ctx.disc));
    PetscCall(ctx.beginAssembly());
    PetscCall(ctx.disc->cellGuard(xl.get(), exactBelow, guard));
    if (ref) {
      any = safeguard.rejects(*ref, *guard, bandTop) ? 1 : 0;
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, PetscObjectComm((PetscObject)xg)));
    }
    if (bad) *bad = any != 0;
    if (!any) PetscCall(ctx.disc->objective(xl.get(), e, nullptr));
    PetscCall(ctx.endAssembly());
    PetscFunctionReturn(0);
  }
};

// The local update x - t p from x (energy `energy`, guard values `ref`; slope = g . p > 0): t halved from 1 until the
// safeguard accepts it and the energy falls by Armijo's share of t slope. A full step is then doubled, up to
// `doublings` times, while each doubling lowers the energy by at least what the full step lowered it (the local
// problems creep along negative or overstated curvature as the global ones do: -newton_extrapolate, SubspaceStep) and
// the safeguard accepts it. *accepted false: no length was accepted; else `trial`, *e and *alpha hold the update.
// p is overwritten by the doublings.
PetscErrorCode searchLocalUpdate(LocalTrial &lt, Vec x, Vec p, PetscReal slope, PetscReal energy,
                                 const std::vector<double> &ref, PetscInt doublings, Vec trial, PetscReal *e,
                                 std::vector<double> *alpha, bool *accepted) {
  bool bad = true;
  double t = 1.0;
  PetscFunctionBeginUser;
  *accepted = false;
  for (int k = 0; k < kMaxCuts; ++k, t *= 0.5) {
    PetscCall(VecWAXPY(trial, -t, p, x));
    PetscCall(lt.evaluate(trial, &ref, alpha, e, &bad));
    *accepted = !bad && *e <= energy - kArmijo * t * slope;
    if (*accepted) break;
  }
  if (!*accepted || t < 1.0) PetscFunctionReturn(0);
  const double gain = energy - *e;
  std::vector<double> alphaLonger;
  for (PetscInt k = 0; k < doublings; ++k) {
    PetscReal eLonger;
    PetscCall(VecWAXPY(p, -1.0, x, trial));  // trial = x - s p_0, so 2 trial - x = x - 2 s p_0 (p is spent)
    PetscCall(VecAYPX(p, 1.0, trial));
    PetscCall(lt.evaluate(p, &ref, &alphaLonger, &eLonger, &bad));
    if (bad || !(eLonger <= *e - gain)) break;
    PetscCall(VecCopy(p, trial));
    *e = eLonger;
    alpha->swap(alphaLonger);
  }
  PetscFunctionReturn(0);
}

}  // namespace

// The local set of the update that just ended (x - local_.before): 1 in `mark` (global) at the dofs of the moved
// vertices and their neighbours, and the discretization focused on the cells that touch them. *found false (no focus)
// where the update is not concentrated. Rank-independent: the moved dofs by a global threshold, the neighbours through
// the cells, each counted on the rank that owns it.
PetscErrorCode NewtonSolver::localSet(Vec x, Vec mark, bool *found) {
  const DM dm = ctx_.disc->dm();
  Vec d = ctx_.work;
  PetscReal dmax;
  PetscInt n, N;
  PetscScalar *m;
  const PetscScalar *da;
  PetscFunctionBeginUser;
  *found = false;
  PetscCall(VecWAXPY(d, -1.0, local_.before, x));
  PetscCall(VecNorm(d, NORM_INFINITY, &dmax));
  if (!(dmax > 0.0)) PetscFunctionReturn(0);
  PetscCall(VecGetLocalSize(d, &n));
  PetscCall(VecGetSize(d, &N));
  PetscCall(VecGetArrayRead(d, &da));
  PetscCall(VecGetArray(mark, &m));
  double sums[3] = {0.0, 0.0, 0.0};  // squared length of the moved dofs, of all, number moved
  for (PetscInt i = 0; i < n; ++i) {
    const double a = std::abs(da[i]);
    const bool moved = a > kMovingShare * dmax;
    m[i] = moved ? 1.0 : 0.0;
    sums[1] += a * a;
    if (moved) {
      sums[0] += a * a;
      sums[2] += 1.0;
    }
  }
  PetscCall(VecRestoreArray(mark, &m));
  PetscCall(VecRestoreArrayRead(d, &da));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, sums, 3, MPI_DOUBLE, MPI_SUM, PetscObjectComm((PetscObject)x)));
  if (sums[0] < kConcentration * sums[1] || sums[2] > kMaxDofShare * static_cast<double>(N)) PetscFunctionReturn(0);
  {
    LocalVec ml(dm), ring(dm);
    PetscCall(ml.fromGlobal(mark, nullptr));
    PetscCall(ctx_.disc->setFocus(ml.get()));  // the cells of the moved vertices
    PetscCall(ring.zeros());
    PetscCall(ctx_.disc->markFocusVertices(ring.get()));  // their vertices: the moved ones and their neighbours
    PetscCall(VecSet(mark, 0.0));
    PetscCall(DMLocalToGlobal(dm, ring.get(), ADD_VALUES, mark));
  }
  LocalVec ml(dm);
  PetscCall(ml.fromGlobal(mark, nullptr));
  PetscCall(ctx_.disc->setFocus(ml.get()));  // every cell that touches a vertex of the local set
  *found = true;
  PetscFunctionReturn(0);
}

PetscErrorCode NewtonSolver::localSolve(Vec x, Vec F, PetscReal *fnorm) {
  fem::Discretization *disc = ctx_.disc;
  const DM dm = disc->dm();
  const MPI_Comm comm = PetscObjectComm((PetscObject)x);
  Vec mark, g, p, trial;
  bool found = false;
  PetscFunctionBeginUser;
  PetscCall(VecDuplicate(x, &mark));
  PetscCall(localSet(x, mark, &found));
  if (!found) {
    PetscCall(VecDestroy(&mark));
    PetscFunctionReturn(0);
  }
  IS is;
  PetscCall(localRows(mark, &is));
  if (!local_.ksp) {
    PC pc;
    PetscCall(KSPCreate(comm, &local_.ksp));
    PetscCall(KSPSetType(local_.ksp, KSPCG));
    PetscCall(KSPGetPC(local_.ksp, &pc));
    PetscCall(PCSetType(pc, PCJACOBI));
    PetscCall(KSPSetTolerances(local_.ksp, kLocalRtol, PETSC_DEFAULT, PETSC_DEFAULT, kLocalMaxIts));
  }
  PetscCall(KSPReset(local_.ksp));  // a new set: new sizes
  PetscCall(VecDuplicate(x, &g));
  PetscCall(VecDuplicate(x, &p));
  PetscCall(VecDuplicate(x, &trial));
  // The local systems are filtered as the global ones (clamped where this iteration's was unfiltered: an exact local
  // system is as indefinite as the update that made the set).
  const kernels::EigenFilter filterBefore = disc->eigenFilter();
  if (filterBefore == kernels::EigenFilter::None) disc->setEigenFilter(kernels::EigenFilter::Clamp);
  LocalTrial lt{ctx_, *safeguard_, {}};
  disc->mollifierBandTop(&lt.bandTop);
  lt.exactBelow = safeguard_->exactBelow(lt.bandTop);
  std::vector<double> ref, alpha;
  PetscReal energy;
  PetscCall(lt.evaluate(x, nullptr, &ref, &energy, nullptr));
  Mat Hs = nullptr;
  const PetscInt before = ctx_.result.localIterations;
  for (PetscInt it = 0; it < opts_.local.maxIterations; ++it) {
    {
      LocalVec xl(dm), gl(dm);
      PetscCall(xl.fromGlobal(x, disc));
      PetscCall(gl.zeros());
      PetscCall(gradientAt(xl.get(), gl.get(), g));
      // Backward Euler's bound on the local step (NewtonContext::stepBound; the local system, filtered, is at least
      // its mass term): where even the bound is within the tolerance there is nothing to solve for.
      PetscReal bound;
      PetscCall(VecPointwiseMult(p, g, mark));
      PetscCall(ctx_.stepBound(p, &bound));
      if (bound <= ctx_.stepTol) break;
      PetscCall(ctx_.beginAssembly());
      PetscCall(disc->hessian(xl.get(), ctx_.J));  // the set's rows are whole: every cell that touches them
      PetscCall(ctx_.endAssembly());
    }
    Vec gs, ps;
    PetscCall(MatDestroy(&Hs));
    PetscCall(MatCreateSubMatrix(ctx_.J, is, is, MAT_INITIAL_MATRIX, &Hs));
    PetscCall(KSPSetOperators(local_.ksp, Hs, Hs));
    PetscCall(VecGetSubVector(g, is, &gs));
    PetscCall(VecDuplicate(gs, &ps));
    PetscCall(KSPSolve(local_.ksp, gs, ps));
    PetscCall(VecRestoreSubVector(g, is, &gs));
    PetscCall(VecSet(p, 0.0));
    PetscCall(VecISCopy(p, is, SCATTER_FORWARD, ps));
    PetscCall(VecDestroy(&ps));
    PetscReal pinf, slope;
    PetscCall(VecNorm(p, NORM_INFINITY, &pinf));
    PetscCall(VecDot(g, p, &slope));
    if (pinf <= ctx_.stepTol || !(slope > 0.0)) break;  // converged locally, or no descent
    bool accepted = false;
    PetscReal e = 0.0;
    PetscCall(
        searchLocalUpdate(lt, x, p, slope, energy, ref, opts_.subspace.extrapolate, trial, &e, &alpha, &accepted));
    if (!accepted) break;
    PetscCall(VecCopy(trial, x));
    energy = e;
    ref.swap(alpha);
    ++ctx_.result.localIterations;
  }
  disc->setEigenFilter(filterBefore);
  PetscCall(disc->setFocus(nullptr));
  PetscCall(MatDestroy(&Hs));
  PetscCall(ISDestroy(&is));
  for (Vec *v : {&mark, &g, &p, &trial}) PetscCall(VecDestroy(v));
  if (ctx_.result.localIterations > before) {  // the whole gradient again, for the global solve that follows
    PetscCall(SNESComputeFunction(ctx_.snes, x, F));
    PetscCall(VecNorm(F, NORM_2, fnorm));
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::solver
