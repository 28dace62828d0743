// One term of the total potential (elastic cells, bending hinges, obstacle contact, inertia + gravity, surface
// loads): its value, gradient, Hessian and true curvature on this rank's share of a local state (a DMPlex local
// vector, Dirichlet values filled), each implemented once, in the term's own file. The discretization's objective,
// gradient, Hessian and curvature Gram matrix are loops over the active terms (assembly.cpp), in a fixed order so
// results do not depend on anything but the state.
#pragma once

#include "energies/energy.hpp"
#include "fem/terms/element_scatter.hpp"
#include "fem/vertex_layout.hpp"

#include <petscmat.h>

#include <Eigen/Core>

namespace aries::fem {

// How the Hessian is assembled: the element Hessians' eigenvalue filter (projected Newton) and whether the matrix
// takes blocks of the vertex dofs (BAIJ with bs = dofs per vertex) or scalar entries (AIJ: for GAMG, or where a vertex
// is held in some components only).
struct HessianAssembly {
  energies::HessianFilter filter;
  bool blocked = true;
  bool wholeElement = false;  // filter each element's whole Hessian instead of each point's (-psd_scope element)
  // Product mode (Discretization::hessianProduct): no matrix; each element or vertex matrix K (the same filtered one)
  // adds K d into y, local layouts, over every dof of its vertices, prescribed ones included: the rows of the free
  // dofs then hold H_ff d_f + H_fd d_d (the lifted Dirichlet increment's coupling when d is zero at the free dofs).
  const PetscScalar *productIn = nullptr;
  PetscScalar *productOut = nullptr;
  // Pattern mode (Discretization::preallocateHessian): only where entries go counts; a term may add zero matrices
  // instead of evaluating its Hessian, through the same insertions.
  bool patternOnly = false;
  bool product() const { return productOut != nullptr; }
};

// The K x K Gram matrix d_k^T H d_l of at most kMaxGramDirections directions, accumulated term by term.
constexpr int kMaxGramDirections = 8;
using GramMatrix = Eigen::Matrix<double, kMaxGramDirections, kMaxGramDirections>;

class Term {
 public:
  virtual ~Term() = default;
  virtual const char *name() const = 0;
  // Adds this rank's share of the energy to *energy and the sum of the absolute values of its pieces (the scale of
  // its round-off) to *magnitude; both as one partial sum per term.
  virtual void addEnergy(const PetscScalar *x, double *energy, double *magnitude) const = 0;
  // Adds the gradient into g (local vector layout; shared vertices are summed by the local-to-global scatter).
  virtual void addGradient(const PetscScalar *x, PetscScalar *g) const = 0;
  // Adds the (filtered, for element terms) Hessian into J with ADD_VALUES; assembly is finished by the caller.
  virtual PetscErrorCode addHessian(const PetscScalar *x, const HessianAssembly &how, Mat J) const = 0;
  // Adds d_k^T H d_l with the true (unfiltered) Hessian for the K directions d[k] (local layout, zero at Dirichlet
  // dofs) into the top-left K x K block of q.
  virtual void addCurvature(const PetscScalar *x, const PetscScalar *const d[], int K, GramMatrix *q) const = 0;
  // Values this term adds to rows another rank owns in one Hessian assembly (an upper bound), to size PETSc's stash.
  virtual PetscInt offRankHessianValues() const { return 0; }
};

// Adds an element matrix K (row-major, (NV R) x (NV R), R dofs per vertex of the element's NV local vertices) into J:
// as R x R blocks into BAIJ, or entry by entry into AIJ; prescribed dofs are skipped (negative rows).
// In product mode (how.product()) it adds K d into y instead, over all of the element's dofs.
template <int NV, int R, class Vertices>
inline PetscErrorCode addElementMatrix(const VertexTable &verts, const Vertices &vertex, const double *K,
                                       const HessianAssembly &how, Mat J) {
  PetscFunctionBeginUser;
  if (how.product()) {
    for (int v = 0; v < NV; ++v)
      for (int i = 0; i < R; ++i) {
        const double *row = K + (v * R + i) * (NV * R);
        double sum = 0.0;
        for (int w = 0; w < NV; ++w)
          for (int j = 0; j < R; ++j) sum += row[w * R + j] * how.productIn[verts[vertex[w]].loc + j];
        how.productOut[verts[vertex[v]].loc + i] += sum;
      }
  } else {
    PetscCall((setElementMatrix<NV, R>(verts, vertex, K, how.blocked, J)));
  }
  PetscFunctionReturn(0);
}

// Product mode: an element none of whose dofs d touches adds nothing (K d = 0), so its matrix need not be evaluated
// (the lifted increment's d lives on the supports: only the elements next to them count).
template <int NV, int R, class Vertices>
inline bool productSkips(const VertexTable &verts, const Vertices &vertex, const HessianAssembly &how) {
  if (!how.product()) return false;
  for (int v = 0; v < NV; ++v)
    for (int i = 0; i < R; ++i)
      if (how.productIn[verts[vertex[v]].loc + i] != 0.0) return false;
  return true;
}

// Accumulates sum_kl a_k^T M a_l for a term's pieces a_k of the K directions (the columns of A).
template <class DirMat, class HessMat>
inline void addGram(const DirMat &A, const HessMat &M, int K, GramMatrix *q) {
  const auto MA = (M * A).eval();
  q->topLeftCorner(K, K) += A.transpose() * MA;
}

}  // namespace aries::fem
