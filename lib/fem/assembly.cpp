// The total potential and its derivatives as loops over the active terms (terms/), in their fixed order.
#include "fem/discretization_impl.hpp"
#include "fem/hessian_pattern.hpp"

#include <cmath>

namespace aries::fem {

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::objective(Vec xLocal, PetscReal *value, PetscReal *magnitude) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(xLocal, &x));
  double sums[2] = {0.0, 0.0};  // energy, magnitude
  for (const Term *t : terms_) t->addEnergy(x, &sums[0], &sums[1]);
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  if (std::isnan(sums[0])) sums[0] = PETSC_INFINITY;  // an undefined state is never accepted by the line search
  double tot[2];
  PetscCallMPI(MPI_Allreduce(sums, tot, magnitude ? 2 : 1, MPI_DOUBLE, MPI_SUM, comm()));
  *value = tot[0];
  if (magnitude) *magnitude = tot[1];
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::elasticEnergy(Vec xLocal, PetscReal *value) const {
  const PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(VecGetArrayRead(xLocal, &x));
  double e = 0.0, magnitude = 0.0;
  cells_.addEnergy(x, &e, &magnitude);
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscCallMPI(MPI_Allreduce(&e, value, 1, MPI_DOUBLE, MPI_SUM, comm()));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::gradient(Vec xLocal, Vec gLocal) const {
  const PetscScalar *x;
  PetscScalar *g;
  PetscFunctionBeginUser;
  PetscCall(VecSet(gLocal, 0.0));
  PetscCall(VecGetArrayRead(xLocal, &x));
  PetscCall(VecGetArray(gLocal, &g));
  for (const Term *t : terms_) t->addGradient(x, g);
  PetscCall(VecRestoreArray(gLocal, &g));
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::hessian(Vec xLocal, Mat J) {
  const PetscScalar *x;
  PetscInt bs;
  PetscFunctionBeginUser;
  PetscCall(MatGetBlockSize(J, &bs));
  const HessianAssembly how{hessianFilter_, bs == R, wholeElementFilter_};
  if (!stashSized_) {
    // Entries for rows another rank owns go through PETSc's stash, which otherwise grows by reallocation during the
    // first assembly: size it for every off-rank value the terms add.
    PetscInt values = 0;
    for (const Term *t : terms_) values += t->offRankHessianValues();
    PetscCall(MatStashSetInitialSize(J, how.blocked ? 0 : values, how.blocked ? values : 0));
    stashSized_ = true;
  }
  PetscCall(MatZeroEntries(J));
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (const Term *t : terms_) PetscCall(t->addHessian(x, how, J));
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscCall(MatAssemblyBegin(J, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(J, MAT_FINAL_ASSEMBLY));
  PetscFunctionReturn(0);
}

// The pattern is recorded from every term's (unfiltered) Hessian at the rest state, added by the same calls as
// hessian(), so every coupling a term makes is preallocated (fem/hessian_pattern.hpp: an entry a term adds elsewhere
// later would stop the assembly with PETSc's new-nonzero error, not go unnoticed). DMPlex's own preallocation walks
// each vertex's star and closure instead: 3.9 s of a 5.7 s setup for 126k tets on 2 ranks (bench/peer.py's box),
// where this costs 0.13 s.
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::preallocateHessian(Mat J) const {
  PetscInt bs;
  Vec xLocal;
  PetscScalar *x;
  PetscFunctionBeginUser;
  PetscCall(MatGetBlockSize(J, &bs));
  HessianPattern pattern;
  PetscCall(pattern.create(J));
  PetscCall(DMGetLocalVector(mesh_->dm, &xLocal));
  PetscCall(VecGetArray(xLocal, &x));
  for (const auto &vi : verts_)
    for (int i = 0; i < R; ++i) x[vi.loc + i] = vi.rest[i];
  energies::HessianFilter unfiltered = hessianFilter_;
  unfiltered.filter = kernels::EigenFilter::None;  // the pattern only: no eigensolves
  HessianAssembly how{unfiltered, bs == R, false};
  how.patternOnly = true;
  for (const Term *t : terms_) PetscCall(t->addHessian(x, how, pattern.recorder()));
  PetscCall(VecRestoreArray(xLocal, &x));
  PetscCall(DMRestoreLocalVector(mesh_->dm, &xLocal));
  PetscCall(pattern.preallocate(J));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::hessianProduct(Vec xLocal, Vec dLocal, Vec yLocal) const {
  const PetscScalar *x, *d;
  PetscScalar *y;
  PetscFunctionBeginUser;
  PetscCall(VecSet(yLocal, 0.0));
  PetscCall(VecGetArrayRead(xLocal, &x));
  PetscCall(VecGetArrayRead(dLocal, &d));
  PetscCall(VecGetArray(yLocal, &y));
  HessianAssembly how{hessianFilter_, true, wholeElementFilter_};
  how.productIn = d;
  how.productOut = y;
  for (const Term *t : terms_) PetscCall(t->addHessian(x, how, nullptr));
  PetscCall(VecRestoreArray(yLocal, &y));
  PetscCall(VecRestoreArrayRead(dLocal, &d));
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  PetscFunctionReturn(0);
}

template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::curvatureGram(Vec xLocal, const std::vector<Vec> &dLocal,
                                                   std::vector<double> *gram) const {
  const int K = static_cast<int>(dLocal.size());
  const PetscScalar *x, *d[kMaxGramDirections];
  PetscFunctionBeginUser;
  if (K > kMaxGramDirections)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_ARG_OUTOFRANGE, "curvatureGram: at most %d directions", kMaxGramDirections);
  PetscCall(VecGetArrayRead(xLocal, &x));
  for (int k = 0; k < K; ++k) PetscCall(VecGetArrayRead(dLocal[k], &d[k]));
  GramMatrix q = GramMatrix::Zero();
  for (const Term *t : terms_) t->addCurvature(x, d, K, &q);
  for (int k = 0; k < K; ++k) PetscCall(VecRestoreArrayRead(dLocal[k], &d[k]));
  PetscCall(VecRestoreArrayRead(xLocal, &x));
  std::vector<double> local(K * K);
  for (int k = 0; k < K; ++k)
    for (int l = 0; l < K; ++l) local[k * K + l] = 0.5 * (q(k, l) + q(l, k));
  gram->resize(K * K);
  PetscCallMPI(MPI_Allreduce(local.data(), gram->data(), K * K, MPI_DOUBLE, MPI_SUM, comm()));
  PetscFunctionReturn(0);
}

ARIES_INSTANTIATE_FOR_ELEMENT_TYPES(DiscretizationT)

}  // namespace aries::fem
