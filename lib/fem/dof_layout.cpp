// DOF layout: which vertex components are Dirichlet (-bc_clamp sets, -bc_box boxes, all components or those of
// _components), the PetscSection with them constrained (the global vector holds the free dofs only), the vertex table
// and the clamp centers.
#include "fem/discretization_impl.hpp"

#include "fem/boundary.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

#include <algorithm>

namespace aries::fem {

using core::sharedLeafPoints;
using core::CentroidAccumulator;

// Per DM point and component (bcFlag[3 p + i], the sets of bc_, from the options): the index of the first Dirichlet
// set (clamp sets, then boxes) that prescribes component i of a vertex, PETSC_MAX_INT if none; every copy of a shared
// vertex agrees (a boundary face may live on one rank only).
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::markDirichlet(const Mesh &mesh, const std::vector<Eigen::Vector3d> &rest,
                                                    std::vector<PetscInt> *bcFlagOut) {
  PetscInt pStart, pEnd;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(mesh.dm, &pStart, &pEnd));
  std::vector<PetscInt> &bcFlag = *bcFlagOut;
  bcFlag.assign(3 * (pEnd - pStart), PETSC_MAX_INT);
  const auto mark = [&](PetscInt p, size_t s) {
    for (int i = 0; i < R; ++i)
      if (bc_.sets[s].components & (1u << i))
        bcFlag[3 * (p - pStart) + i] = std::min<PetscInt>(bcFlag[3 * (p - pStart) + i], static_cast<PetscInt>(s));
  };
  for (size_t s = 0; s < bc_.sets.size(); ++s)
    if (R == 2 && bc_.sets[s].componentsGiven && (bc_.sets[s].components & 4u)) {
      const bool isBox = s >= bc_.numGroups();
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -bc_%s_%s_components: z on a 2D mesh (use x, y)",
              isBox ? "box" : "clamp",
              isBox ? std::to_string(s - bc_.numGroups() + 1).c_str() : bc_.sets[s].id.c_str());
    }
  for (size_t s = 0; s < bc_.numGroups(); ++s) {
    std::vector<PetscInt> vs;
    bool found = false;
    PetscCall(physicalGroupVertices(mesh, bc_.sets[s].id, &vs, &found));
    if (!found) {
      std::string known;
      PetscCall(describePhysicalGroups(mesh, &known));
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -bc_clamp: boundary set '%s' does not exist in mesh '%s' (physical groups present: %s)",
              bc_.sets[s].id.c_str(), mesh.filename.c_str(), known.c_str());
    }
    for (PetscInt v : vs) mark(v, s);
  }
  std::vector<char> onBoundary;  // for boxes that hold their boundary vertices only (-bc_box_<k>_surface)
  if (std::any_of(bc_.sets.begin(), bc_.sets.end(), [](const ClampSet &c) { return c.surfaceOnly; }))
    PetscCall(boundaryVertexFlags(mesh, &onBoundary));
  for (size_t b = 0; b < bc_.boxes.size(); ++b) {
    const auto &bb = bc_.boxes[b];
    const bool surfaceOnly = bc_.sets[bc_.numGroups() + b].surfaceOnly;
    for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
      const Eigen::Vector3d &X = rest[v - mesh.vStart];
      if (surfaceOnly && !onBoundary[v - mesh.vStart]) continue;
      if (X[0] >= bb[0] && X[0] <= bb[1] && X[1] >= bb[2] && X[1] <= bb[3] && X[2] >= bb[4] && X[2] <= bb[5])
        mark(v, bc_.numGroups() + b);
    }
  }
  PetscSF pointSF;
  PetscCall(DMGetPointSF(mesh.dm, &pointSF));
  std::vector<PetscInt> leaf(pEnd - pStart), root(pEnd - pStart);
  for (int i = 0; i < 3; ++i) {
    for (PetscInt p = 0; p < pEnd - pStart; ++p) leaf[p] = bcFlag[3 * p + i];
    root = leaf;
    PetscCall(PetscSFReduceBegin(pointSF, MPIU_INT, leaf.data(), root.data(), MPI_MIN));
    PetscCall(PetscSFReduceEnd(pointSF, MPIU_INT, leaf.data(), root.data(), MPI_MIN));
    PetscCall(PetscSFBcastBegin(pointSF, MPIU_INT, root.data(), leaf.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(pointSF, MPIU_INT, root.data(), leaf.data(), MPI_REPLACE));
    for (PetscInt p = 0; p < pEnd - pStart; ++p) bcFlag[3 * p + i] = std::min(leaf[p], root[p]);
  }
  PetscFunctionReturn(0);
}

// The section (the prescribed components of Dirichlet vertices constrained), the matrix type (BAIJ, bs = R, unless
// a vertex is prescribed in some components only: AIJ), the vertex table and the clamp centers (default: the centroid
// of each set at rest over its owned vertices on all ranks).
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::layoutDofs(const Mesh &mesh, const std::vector<Eigen::Vector3d> &rest,
                                                 const std::vector<PetscInt> &bcFlag) {
  DM dm = mesh.dm;
  PetscInt pStart, pEnd;
  PetscSection section;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  const auto fixedComps = [&](PetscInt v, PetscInt comps[3]) {
    PetscInt n = 0;
    for (int i = 0; i < R; ++i)
      if (bcFlag[3 * (v - pStart) + i] != PETSC_MAX_INT) comps[n++] = i;
    return n;
  };
  PetscCall(PetscSectionCreate(comm(), &section));
  PetscCall(PetscSectionSetNumFields(section, 1));
  PetscCall(PetscSectionSetFieldComponents(section, 0, R));
  PetscCall(PetscSectionSetChart(section, pStart, pEnd));
  PetscInt partial = 0;  // vertices prescribed in some components only
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    PetscInt comps[3];
    const PetscInt n = fixedComps(v, comps);
    PetscCall(PetscSectionSetDof(section, v, R));
    PetscCall(PetscSectionSetFieldDof(section, v, 0, R));
    if (n > 0) {
      PetscCall(PetscSectionSetConstraintDof(section, v, n));
      PetscCall(PetscSectionSetFieldConstraintDof(section, v, 0, n));
    }
    partial += n > 0 && n < R;
  }
  PetscCall(PetscSectionSetUp(section));
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    PetscInt comps[3];
    if (fixedComps(v, comps) > 0) {
      PetscCall(PetscSectionSetConstraintIndices(section, v, comps));
      PetscCall(PetscSectionSetFieldConstraintIndices(section, v, 0, comps));
    }
  }
  PetscCall(DMSetLocalSection(dm, section));
  PetscCall(PetscSectionDestroy(&section));
  PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &partial, 1, MPIU_INT, MPI_SUM, comm()));
  PetscCall(DMSetMatType(dm, partial ? MATAIJ : MATBAIJ));  // BAIJ blocks need every vertex's R dofs
  PetscSection localSection, globalSection;
  PetscCall(DMGetLocalSection(dm, &localSection));
  PetscCall(DMGetGlobalSection(dm, &globalSection));

  std::vector<char> sharedCopy;  // copies of another rank's points (leaves of the point SF)
  PetscCall(sharedLeafPoints(dm, &sharedCopy));
  verts_.resize(mesh.vEnd - mesh.vStart);
  PetscInt numBcOwned = 0;
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    VertexInfo &vi = verts_[v - mesh.vStart];
    PetscCall(PetscSectionGetOffset(localSection, v, &vi.loc));
    vi.owned = !sharedCopy[v - pStart];
    vi.bcSet = -1;
    vi.numFree = 0;
    for (int i = 0; i < R; ++i) {
      const PetscInt s = bcFlag[3 * (v - pStart) + i];
      vi.fixedBy[i] = s == PETSC_MAX_INT ? -1 : static_cast<int>(s);
      if (vi.fixedBy[i] >= 0 && (vi.bcSet < 0 || vi.fixedBy[i] < vi.bcSet)) vi.bcSet = vi.fixedBy[i];
      vi.numFree += vi.fixedBy[i] < 0;
    }
    vi.rest = rest[v - mesh.vStart];
    vi.global = -1;
    if (vi.numFree > 0) {
      PetscInt goff;
      PetscCall(PetscSectionGetOffset(globalSection, v, &goff));
      vi.global = goff >= 0 ? goff : -(goff + 1);
    }
    if (vi.bcSet >= 0 && vi.owned) ++numBcOwned;
  }
  PetscCallMPI(MPI_Allreduce(&numBcOwned, &numBcGlobal_, 1, MPIU_INT, MPI_SUM, comm()));
  for (size_t s = 0; s < bc_.sets.size(); ++s) {
    if (bc_.sets[s].centerGiven) continue;
    CentroidAccumulator acc;
    for (const auto &vi : verts_)
      if (vi.owned && std::find(vi.fixedBy.begin(), vi.fixedBy.end(), static_cast<int>(s)) != vi.fixedBy.end())
        acc.add(vi.rest);
    Eigen::Vector3d center;
    double count;
    PetscCall(acc.reduce(comm(), &center, &count));
    if (count > 0) bc_.sets[s].center = center;
  }
  PetscFunctionReturn(0);
}

ARIES_INSTANTIATE_FOR_ELEMENT_TYPES(DiscretizationT)

}  // namespace aries::fem
