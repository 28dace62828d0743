#include "fem/harmonic.hpp"

#include <petscksp.h>

namespace aries::fem {

PetscErrorCode harmonicExtension(const Mesh &mesh, HarmonicProblem *p) {
  MPI_Comm comm;
  DM dm = mesh.dm;
  const int nv = p->verticesPerCell, nc = p->components;
  PetscFunctionBeginUser;
  // One entry per DM cell below (cellOwned, closures): a quadratic mesh's DM cells are not its elements.
  PetscCheck(!mesh.quadratic, PETSC_COMM_SELF, PETSC_ERR_SUP, "the harmonic extension needs a linear mesh");
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscInt pStart, pEnd;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));

  // Scalar problem on a clone of the DM: 1 dof per vertex, constrained vertices eliminated.
  DM sdm;
  PetscCall(DMClone(dm, &sdm));
  PetscSection sec;
  PetscCall(PetscSectionCreate(comm, &sec));
  PetscCall(PetscSectionSetChart(sec, pStart, pEnd));
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    PetscCall(PetscSectionSetDof(sec, v, 1));
    if (p->constrained[v - mesh.vStart]) PetscCall(PetscSectionSetConstraintDof(sec, v, 1));
  }
  PetscCall(PetscSectionSetUp(sec));
  const PetscInt zero = 0;
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v)
    if (p->constrained[v - mesh.vStart]) PetscCall(PetscSectionSetConstraintIndices(sec, v, &zero));
  PetscCall(DMSetLocalSection(sdm, sec));
  PetscCall(PetscSectionDestroy(&sec));
  PetscCall(DMSetMatType(sdm, MATAIJ));
  PetscSection gsec, lsec;
  PetscCall(DMGetGlobalSection(sdm, &gsec));
  PetscCall(DMGetLocalSection(sdm, &lsec));
  Mat K;
  std::vector<Vec> b(nc), x(nc);
  PetscCall(DMCreateMatrix(sdm, &K));
  for (int k = 0; k < nc; ++k) {
    PetscCall(DMCreateGlobalVector(sdm, &b[k]));
    PetscCall(VecDuplicate(b[k], &x[k]));
    PetscCall(VecSet(b[k], 0.0));
  }
  std::vector<PetscInt> verts, rows(nv);
  std::vector<double> Ke(nv * nv);
  for (PetscInt c = mesh.cStart; c < mesh.cEnd; ++c) {
    if (!mesh.cellOwned[c - mesh.cStart]) continue;
    PetscCall(closureVertices(mesh, c, &verts));
    p->cellStiffness(c - mesh.cStart, verts.data(), Ke.data());
    for (int i = 0; i < nv; ++i) {
      PetscInt off;
      PetscCall(PetscSectionGetOffset(gsec, verts[i] + mesh.vStart, &off));
      rows[i] = p->constrained[verts[i]] ? -1 : (off >= 0 ? off : -(off + 1));
    }
    PetscCall(MatSetValues(K, nv, rows.data(), nv, rows.data(), Ke.data(), ADD_VALUES));
    // Known values move to the right-hand side.
    for (int i = 0; i < nv; ++i) {
      if (rows[i] < 0) continue;
      for (int j = 0; j < nv; ++j) {
        if (!p->constrained[verts[j]]) continue;
        for (int k = 0; k < nc; ++k)
          PetscCall(VecSetValue(b[k], rows[i], -Ke[i * nv + j] * p->values[static_cast<size_t>(verts[j]) * nc + k],
                                ADD_VALUES));
      }
    }
  }
  PetscCall(MatAssemblyBegin(K, MAT_FINAL_ASSEMBLY));
  PetscCall(MatAssemblyEnd(K, MAT_FINAL_ASSEMBLY));
  KSP ksp;
  PC pc;
  PetscCall(KSPCreate(comm, &ksp));
  PetscCall(KSPSetOptionsPrefix(ksp, p->prefix.c_str()));
  PetscCall(KSPSetOperators(ksp, K, K));
  PetscCall(KSPSetType(ksp, KSPCG));
  PetscCall(KSPGetPC(ksp, &pc));
  PetscCall(PCSetType(pc, PCGAMG));
  PetscCall(KSPSetTolerances(ksp, 1e-10, PETSC_DEFAULT, PETSC_DEFAULT, 10000));
  PetscCall(KSPSetFromOptions(ksp));
  Vec loc;
  PetscCall(DMGetLocalVector(sdm, &loc));
  for (int k = 0; k < nc; ++k) {
    PetscCall(VecAssemblyBegin(b[k]));
    PetscCall(VecAssemblyEnd(b[k]));
    PetscCall(KSPSolve(ksp, b[k], x[k]));
    KSPConvergedReason reason;
    PetscCall(KSPGetConvergedReason(ksp, &reason));
    PetscCheck(reason > 0, comm, PETSC_ERR_NOT_CONVERGED, "the %s's linear solve did not converge (%s; options prefix -%s)",
               p->what.c_str(), KSPConvergedReasons[reason], p->prefix.c_str());
    const PetscScalar *a;
    PetscCall(DMGlobalToLocal(sdm, x[k], INSERT_VALUES, loc));
    PetscCall(VecGetArrayRead(loc, &a));
    for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
      if (p->constrained[v - mesh.vStart]) continue;
      PetscInt off;
      PetscCall(PetscSectionGetOffset(lsec, v, &off));
      p->values[static_cast<size_t>(v - mesh.vStart) * nc + k] = a[off];
    }
    PetscCall(VecRestoreArrayRead(loc, &a));
  }
  PetscCall(DMRestoreLocalVector(sdm, &loc));
  PetscCall(KSPDestroy(&ksp));
  PetscCall(MatDestroy(&K));
  for (int k = 0; k < nc; ++k) {
    PetscCall(VecDestroy(&b[k]));
    PetscCall(VecDestroy(&x[k]));
  }
  PetscCall(DMDestroy(&sdm));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
