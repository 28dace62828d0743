// DOF layout: which vertices are Dirichlet (-bc_clamp sets, -bc_box boxes), the PetscSection with every component of
// a Dirichlet vertex constrained (the global vector holds the free dofs only), the vertex table and the clamp centers.
#include "fem/discretization_impl.hpp"

#include "fem/boundary.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

#include <algorithm>

namespace aries::fem {

using core::sharedLeafPoints;
using core::CentroidAccumulator;

// Per DM point (the sets of bc_, from the options): the index of the first Dirichlet set (clamp sets, then boxes) a vertex belongs to, PETSC_MAX_INT if
// none; every copy of a shared vertex agrees (a boundary face may live on one rank only).
template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::markDirichlet(const Mesh &mesh, const std::vector<Eigen::Vector3d> &rest,
                                                    std::vector<PetscInt> *bcFlagOut) {
  PetscInt pStart, pEnd;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(mesh.dm, &pStart, &pEnd));
  std::vector<PetscInt> &bcFlag = *bcFlagOut;
  bcFlag.assign(pEnd - pStart, PETSC_MAX_INT);
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
    for (PetscInt v : vs) bcFlag[v - pStart] = std::min<PetscInt>(bcFlag[v - pStart], static_cast<PetscInt>(s));
  }
  for (size_t b = 0; b < bc_.boxes.size(); ++b) {
    const auto &bb = bc_.boxes[b];
    for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
      const Eigen::Vector3d &X = rest[v - mesh.vStart];
      if (X[0] >= bb[0] && X[0] <= bb[1] && X[1] >= bb[2] && X[1] <= bb[3] && X[2] >= bb[4] && X[2] <= bb[5])
        bcFlag[v - pStart] = std::min<PetscInt>(bcFlag[v - pStart], static_cast<PetscInt>(bc_.numGroups() + b));
    }
  }
  PetscSF pointSF;
  PetscCall(DMGetPointSF(mesh.dm, &pointSF));
  std::vector<PetscInt> root(bcFlag);
  PetscCall(PetscSFReduceBegin(pointSF, MPIU_INT, bcFlag.data(), root.data(), MPI_MIN));
  PetscCall(PetscSFReduceEnd(pointSF, MPIU_INT, bcFlag.data(), root.data(), MPI_MIN));
  PetscCall(PetscSFBcastBegin(pointSF, MPIU_INT, root.data(), bcFlag.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(pointSF, MPIU_INT, root.data(), bcFlag.data(), MPI_REPLACE));
  for (PetscInt p = pStart; p < pEnd; ++p) bcFlag[p - pStart] = std::min(bcFlag[p - pStart], root[p - pStart]);
  PetscFunctionReturn(0);
}

// The section (all components of Dirichlet vertices constrained), BAIJ matrices, the vertex table and the clamp
// centers (default: the centroid of each set at rest over its owned vertices on all ranks).
template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::layoutDofs(const Mesh &mesh, const std::vector<Eigen::Vector3d> &rest,
                                                 const std::vector<PetscInt> &bcFlag) {
  DM dm = mesh.dm;
  PetscInt pStart, pEnd;
  PetscSection section;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  const auto isBc = [&](PetscInt v) { return bcFlag[v - pStart] != PETSC_MAX_INT; };
  PetscCall(PetscSectionCreate(comm(), &section));
  PetscCall(PetscSectionSetNumFields(section, 1));
  PetscCall(PetscSectionSetFieldComponents(section, 0, R));
  PetscCall(PetscSectionSetChart(section, pStart, pEnd));
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    PetscCall(PetscSectionSetDof(section, v, R));
    PetscCall(PetscSectionSetFieldDof(section, v, 0, R));
    if (isBc(v)) {
      PetscCall(PetscSectionSetConstraintDof(section, v, R));
      PetscCall(PetscSectionSetFieldConstraintDof(section, v, 0, R));
    }
  }
  PetscCall(PetscSectionSetUp(section));
  const PetscInt allComps[3] = {0, 1, 2};
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v)
    if (isBc(v)) {
      PetscCall(PetscSectionSetConstraintIndices(section, v, allComps));
      PetscCall(PetscSectionSetFieldConstraintIndices(section, v, 0, allComps));
    }
  PetscCall(DMSetLocalSection(dm, section));
  PetscCall(PetscSectionDestroy(&section));
  PetscCall(DMSetMatType(dm, MATBAIJ));
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
    vi.bcSet = isBc(v) ? static_cast<int>(bcFlag[v - pStart]) : -1;
    vi.rest = rest[v - mesh.vStart];
    vi.global = -1;
    if (vi.bcSet < 0) {
      PetscInt goff;
      PetscCall(PetscSectionGetOffset(globalSection, v, &goff));
      vi.global = goff >= 0 ? goff : -(goff + 1);
    } else if (vi.owned) {
      ++numBcOwned;
    }
  }
  PetscCallMPI(MPI_Allreduce(&numBcOwned, &numBcGlobal_, 1, MPIU_INT, MPI_SUM, comm()));
  for (size_t s = 0; s < bc_.sets.size(); ++s) {
    if (bc_.sets[s].centerGiven) continue;
    CentroidAccumulator acc;
    for (const auto &vi : verts_)
      if (vi.owned && vi.bcSet == static_cast<int>(s)) acc.add(vi.rest);
    Eigen::Vector3d center;
    double count;
    PetscCall(acc.reduce(comm(), &center, &count));
    if (count > 0) bc_.sets[s].center = center;
  }
  PetscFunctionReturn(0);
}

template class DiscretizationT<3, 3>;
template class DiscretizationT<2, 2>;
template class DiscretizationT<3, 2>;

}  // namespace aries::fem
