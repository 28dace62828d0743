// The total potential and its derivatives as loops over the active terms (terms/), in their fixed order.
#include "fem/discretization_impl.hpp"

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

template class DiscretizationT<3, 3>;
template class DiscretizationT<2, 2>;
template class DiscretizationT<3, 2>;
template class DiscretizationT<3, 3, 8>;
template class DiscretizationT<3, 3, 10>;

}  // namespace aries::fem
