// The body's boundary: the facets one cell of the whole mesh holds, and their vertices; and the vertices of any point's
// closure (mesh/mesh.hpp).
#include "mesh/mesh.hpp"

#include "core/parallel.hpp"

#include <petscsf.h>

namespace aries::fem {

// A facet's cells are counted where they are owned (not a point-SF leaf) and summed over the ranks holding the facet:
// without overlap a facet between two ranks has one local cell on each, with overlap a boundary facet of an owned cell
// also sits in a neighbour's overlap; the sum is the facet's cells in the whole mesh either way.
PetscErrorCode bodyBoundaryFacets(const Mesh &mesh, std::vector<PetscInt> *facets) {
  DM dm = mesh.dm;
  PetscSF sf;
  PetscInt pStart, pEnd, fStart, fEnd;
  std::vector<char> leaf;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  PetscCall(DMPlexGetHeightStratum(dm, 1, &fStart, &fEnd));
  PetscCall(core::sharedLeafPoints(dm, &leaf));
  std::vector<PetscInt> owned(pEnd - pStart, 0);
  for (PetscInt f = fStart; f < fEnd; ++f) {
    PetscInt ns;
    const PetscInt *supp;
    PetscCall(DMPlexGetSupportSize(dm, f, &ns));
    PetscCall(DMPlexGetSupport(dm, f, &supp));
    for (PetscInt k = 0; k < ns; ++k) owned[f - pStart] += !leaf[supp[k] - pStart];
  }
  std::vector<PetscInt> total(owned);
  PetscCall(DMGetPointSF(dm, &sf));
  PetscCall(PetscSFReduceBegin(sf, MPIU_INT, owned.data(), total.data(), MPI_SUM));
  PetscCall(PetscSFReduceEnd(sf, MPIU_INT, owned.data(), total.data(), MPI_SUM));
  std::vector<PetscInt> everywhere(total);  // the owner's total on every copy
  PetscCall(PetscSFBcastBegin(sf, MPIU_INT, total.data(), everywhere.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, MPIU_INT, total.data(), everywhere.data(), MPI_REPLACE));
  facets->clear();
  for (PetscInt f = fStart; f < fEnd; ++f)
    if (everywhere[f - pStart] == 1) facets->push_back(f);
  PetscFunctionReturn(0);
}

PetscErrorCode boundaryVertexFlags(const Mesh &mesh, std::vector<char> *onBoundary) {
  std::vector<PetscInt> facets, vs;
  PetscFunctionBeginUser;
  PetscCall(bodyBoundaryFacets(mesh, &facets));
  std::vector<double> flag(static_cast<size_t>(mesh.vEnd - mesh.vStart), 0.0);
  for (PetscInt f : facets) {
    PetscCall(closureVertices(mesh, f, &vs));
    for (PetscInt v : vs) flag[v] = 1.0;
  }
  PetscCall(sumOverSharedVertices(mesh, 1, &flag));  // a vertex on a boundary facet another rank holds
  onBoundary->assign(flag.size(), 0);
  for (size_t v = 0; v < flag.size(); ++v) (*onBoundary)[v] = flag[v] > 0.0;
  PetscFunctionReturn(0);
}

PetscErrorCode closureVertices(const Mesh &mesh, PetscInt point, std::vector<PetscInt> *vertices) {
  PetscInt nc, *closure = nullptr;
  PetscFunctionBeginUser;
  vertices->clear();
  if (!mesh.cellCorners.empty() && point >= mesh.cStart && point < mesh.cEnd) {  // a tetrahedron: its read corners
    const auto first = mesh.cellCorners.begin() + 4 * (point - mesh.cStart);
    vertices->assign(first, first + 4);
    PetscFunctionReturn(0);
  }
  PetscCall(DMPlexGetTransitiveClosure(mesh.dm, point, PETSC_TRUE, &nc, &closure));
  for (PetscInt k = 0; k < nc; ++k)
    if (closure[2 * k] >= mesh.vStart && closure[2 * k] < mesh.vEnd) vertices->push_back(closure[2 * k] - mesh.vStart);
  PetscCall(DMPlexRestoreTransitiveClosure(mesh.dm, point, PETSC_TRUE, &nc, &closure));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
