// Two passes of mesh loading made in one, against the library calls they replace (ctest mesh.loading.*): the cells'
// dual graph (mesh/mesh_partition.cpp: cellDualGraph) against METIS_MeshToDual's on the serial mesh (also where a face
// has three cells or two cells have the same corners), and interpolateMesh (mesh/mesh_interpolate.cpp) against PETSc's
// DMPlexInterpolate: the same distributed mesh of cells and vertices interpolated both ways must give the same DM point
// for point: chart, depth strata, cones, cone orientations, supports, cell types, point SF (leaves and their roots),
// coordinates and labels; and the corners it hands back must be the cells' closure vertices in closure order. Run on 1,
// 2 and 3 ranks, on tetrahedral boxes (cells and their vertices listed in random orders, so faces are met in every
// orientation) and, for the fallback, a hexahedral box; `-mesh_file FILE` adds a mesh file (read as cells and
// vertices), e.g. meshes/cache/bunny_paper.msh. Prints "FAIL: ..." and exits 1 on a failure.
#include "mesh/mesh_loading.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

#include <algorithm>
#include <cstdio>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace {

int failures = 0;
void check(bool ok, const std::string &what) {
  if (!ok) {
    std::printf("FAIL: %s\n", what.c_str());
    ++failures;
  }
}

// cellDualGraph against METIS_MeshToDual (neighbours sharing a face's corners, each list sorted) on this rank's cells.
PetscErrorCode checkDualGraph(DM dm, PetscInt corners, const std::string &what) {
  PetscInt cStart, cEnd, vStart, vEnd, numCells;
  std::vector<idx_t> offsets, adjacency, eptr(1, 0), eind;
  PetscFunctionBeginUser;
  PetscCall(aries::fem::loading::cellDualGraph(dm, &numCells, &offsets, &adjacency));
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  if (cEnd == cStart) PetscFunctionReturn(0);
  for (PetscInt c = cStart; c < cEnd; ++c) {
    const PetscInt *cone;
    PetscCall(DMPlexGetCone(dm, c, &cone));
    for (PetscInt k = 0; k < corners; ++k) eind.push_back(static_cast<idx_t>(cone[k] - vStart));
    eptr.push_back(static_cast<idx_t>(eind.size()));
  }
  idx_t ne = static_cast<idx_t>(cEnd - cStart), nn = static_cast<idx_t>(vEnd - vStart), common = corners == 4 ? 3 : 4;
  idx_t numbering = 0, *xadj = nullptr, *adjncy = nullptr;
  check(METIS_MeshToDual(&ne, &nn, eptr.data(), eind.data(), &common, &numbering, &xadj, &adjncy) == METIS_OK,
        what + ": METIS_MeshToDual");
  for (idx_t c = 0; c < ne; ++c) std::sort(adjncy + xadj[c], adjncy + xadj[c + 1]);
  check(numCells == ne && std::equal(offsets.begin(), offsets.end(), xadj) &&
            std::equal(adjacency.begin(), adjacency.end(), adjncy) && adjacency.size() == size_t(xadj[ne]),
        what + ": dual graph differs from METIS_MeshToDual's");
  METIS_Free(xadj);
  METIS_Free(adjncy);
  PetscFunctionReturn(0);
}

// Meshes METIS's graph must be kept for (cellDualGraph falls back to METIS_MeshToDual): two cells on the same four
// corners, and three cells on one face. Cells on rank 0 only.
PetscErrorCode checkIrregularDualGraphs() {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  const PetscReal coords[] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1, -1, -1, -1};
  const std::vector<std::vector<PetscInt>> meshes = {{0, 1, 2, 3, 1, 0, 2, 3, 1, 2, 3, 4},
                                                     {0, 1, 2, 3, 1, 2, 3, 4, 3, 2, 1, 5}};
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    DM dm;
    const PetscInt numCells = rank == 0 ? static_cast<PetscInt>(meshes[m].size() / 4) : 0;
    PetscCall(DMPlexCreateFromCellListPetsc(PETSC_COMM_WORLD, 3, numCells, rank == 0 ? 6 : 0, 4, PETSC_FALSE,
                                            meshes[m].data(), 3, coords, &dm));
    PetscCall(checkDualGraph(dm, 4, m == 0 ? "two cells on the same corners" : "three cells on a face"));
    PetscCall(DMDestroy(&dm));
  }
  PetscFunctionReturn(0);
}

// A box of n x (n+1) x (n+2) cubes and vertices only (cells made on rank 0, then distributed without overlap), with a
// label on some cells and vertices that must be copied. simplex: six tetrahedra per cube (Kuhn), listed in random order
// with their vertices in a random order of the same parity (seed), so faces are met in every orientation; else the
// cubes as hexahedra.
PetscErrorCode distributedBox(bool simplex, PetscInt n, unsigned seed, DM *out) {
  DM dm, dist = nullptr;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(PETSC_COMM_WORLD, &rank));
  const PetscInt nx = n, ny = n + 1, nz = n + 2;
  auto vertex = [&](PetscInt i, PetscInt j, PetscInt k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  std::vector<PetscInt> cells;
  std::vector<PetscReal> coords;
  std::mt19937 rng(seed);
  if (rank == 0) {
    for (PetscInt k = 0; k <= nz; ++k)
      for (PetscInt j = 0; j <= ny; ++j)
        for (PetscInt i = 0; i <= nx; ++i) coords.insert(coords.end(), {(PetscReal)i, (PetscReal)j, (PetscReal)k});
    const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    std::vector<std::vector<PetscInt>> list;
    for (PetscInt k = 0; k < nz; ++k)
      for (PetscInt j = 0; j < ny; ++j)
        for (PetscInt i = 0; i < nx; ++i) {
          if (!simplex) {  // PETSc's hexahedron: bottom face 0-1-2-3 (inward normal), top 4-5-6-7
            list.push_back({vertex(i, j, k), vertex(i, j + 1, k), vertex(i + 1, j + 1, k), vertex(i + 1, j, k),
                            vertex(i, j, k + 1), vertex(i + 1, j, k + 1), vertex(i + 1, j + 1, k + 1),
                            vertex(i, j + 1, k + 1)});
            continue;
          }
          for (const auto &perm : perms) {  // the path from corner (0,0,0) to (1,1,1) along the axes in this order
            PetscInt at[3] = {i, j, k};
            std::vector<PetscInt> tet{vertex(at[0], at[1], at[2])};
            for (int s = 0; s < 3; ++s) {
              ++at[perm[s]];
              tet.push_back(vertex(at[0], at[1], at[2]));
            }
            for (int swaps = 0; swaps < 2; ++swaps) std::swap(tet[rng() % 4], tet[rng() % 4]);
            list.push_back(tet);
          }
        }
    std::shuffle(list.begin(), list.end(), rng);
    for (const auto &c : list) cells.insert(cells.end(), c.begin(), c.end());
  }
  const PetscInt corners = simplex ? 4 : 8;
  const PetscInt numCells = static_cast<PetscInt>(cells.size()) / corners;
  const PetscInt numVertices = static_cast<PetscInt>(coords.size()) / 3;
  PetscCall(DMPlexCreateFromCellListPetsc(PETSC_COMM_WORLD, 3, numCells, numVertices, corners, PETSC_FALSE,
                                          cells.data(), 3, coords.data(), &dm));
  PetscInt cStart, cEnd, vStart, vEnd;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  PetscCall(checkDualGraph(dm, corners, simplex ? "tetrahedra" : "hexahedra"));
  DMLabel marks;
  PetscCall(DMCreateLabel(dm, "marks"));
  PetscCall(DMGetLabel(dm, "marks", &marks));
  for (PetscInt c = cStart; c < cEnd; c += 7) PetscCall(DMLabelSetValue(marks, c, 1));
  for (PetscInt v = vStart; v < vEnd; v += 5) PetscCall(DMLabelSetValue(marks, v, 2));
  PetscCall(DMPlexDistribute(dm, 0, nullptr, &dist));
  if (dist) {
    PetscCall(DMDestroy(&dm));
    dm = dist;
  }
  *out = dm;
  PetscFunctionReturn(0);
}

PetscErrorCode compare(DM a, DM b, const std::string &what) {
  PetscFunctionBeginUser;
  PetscInt aStart, aEnd, bStart, bEnd;
  PetscCall(DMPlexGetChart(a, &aStart, &aEnd));
  PetscCall(DMPlexGetChart(b, &bStart, &bEnd));
  check(aStart == bStart && aEnd == bEnd, what + ": chart");
  if (aStart != bStart || aEnd != bEnd) PetscFunctionReturn(0);
  for (PetscInt d = 0; d <= 3; ++d) {
    PetscInt as, ae, bs, be;
    PetscCall(DMPlexGetDepthStratum(a, d, &as, &ae));
    PetscCall(DMPlexGetDepthStratum(b, d, &bs, &be));
    check(as == bs && ae == be, what + ": depth stratum " + std::to_string(d));
  }
  int bad = 0;
  for (PetscInt p = aStart; p < aEnd && bad < 5; ++p) {
    PetscInt an, bn, asn, bsn;
    const PetscInt *ac, *bc, *ao, *bo, *as, *bs;
    DMPolytopeType at, bt;
    PetscCall(DMPlexGetConeSize(a, p, &an));
    PetscCall(DMPlexGetConeSize(b, p, &bn));
    PetscCall(DMPlexGetCone(a, p, &ac));
    PetscCall(DMPlexGetCone(b, p, &bc));
    PetscCall(DMPlexGetConeOrientation(a, p, &ao));
    PetscCall(DMPlexGetConeOrientation(b, p, &bo));
    PetscCall(DMPlexGetSupportSize(a, p, &asn));
    PetscCall(DMPlexGetSupportSize(b, p, &bsn));
    PetscCall(DMPlexGetSupport(a, p, &as));
    PetscCall(DMPlexGetSupport(b, p, &bs));
    PetscCall(DMPlexGetCellType(a, p, &at));
    PetscCall(DMPlexGetCellType(b, p, &bt));
    bool same = an == bn && asn == bsn && at == bt && std::equal(ac, ac + an, bc) && std::equal(ao, ao + an, bo) &&
                std::equal(as, as + asn, bs);
    if (!same) ++bad;
    check(same, what + ": point " + std::to_string(p) + " (cone, orientations, support or cell type)");
  }
  // point SF: the same leaves with the same roots
  PetscSF asf, bsf;
  PetscInt anr, bnr, anl, bnl;
  const PetscInt *al, *bl;
  const PetscSFNode *ar, *br;
  PetscCall(DMGetPointSF(a, &asf));
  PetscCall(DMGetPointSF(b, &bsf));
  PetscCall(PetscSFGetGraph(asf, &anr, &anl, &al, &ar));
  PetscCall(PetscSFGetGraph(bsf, &bnr, &bnl, &bl, &br));
  std::vector<std::tuple<PetscInt, PetscInt, PetscInt>> aLeaves, bLeaves;
  for (PetscInt l = 0; l < anl; ++l) aLeaves.emplace_back(al ? al[l] : l, ar[l].rank, ar[l].index);
  for (PetscInt l = 0; l < bnl; ++l) bLeaves.emplace_back(bl ? bl[l] : l, br[l].rank, br[l].index);
  std::sort(aLeaves.begin(), aLeaves.end());
  std::sort(bLeaves.begin(), bLeaves.end());
  check(anr == bnr && aLeaves == bLeaves, what + ": point SF (" + std::to_string(anl) + " against " +
                                              std::to_string(bnl) + " leaves)");
  // coordinates
  Vec ax, bx;
  PetscBool equal = PETSC_FALSE;
  PetscCall(DMGetCoordinatesLocal(a, &ax));
  PetscCall(DMGetCoordinatesLocal(b, &bx));
  PetscCall(VecEqual(ax, bx, &equal));
  check(equal, what + ": coordinates");
  // labels other than depth and celltype (compared above through the strata and the cell types)
  PetscInt na, nb;
  PetscCall(DMGetNumLabels(a, &na));
  PetscCall(DMGetNumLabels(b, &nb));
  check(na == nb, what + ": number of labels");
  for (PetscInt k = 0; k < na; ++k) {
    const char *name;
    DMLabel la, lb;
    PetscCall(DMGetLabelName(a, k, &name));
    PetscCall(DMGetLabel(a, name, &la));
    PetscCall(DMGetLabel(b, name, &lb));
    check(lb != nullptr, what + ": label " + name);
    if (!lb) continue;
    int differ = 0;
    for (PetscInt p = aStart; p < aEnd; ++p) {
      PetscInt va, vb;
      PetscCall(DMLabelGetValue(la, p, &va));
      PetscCall(DMLabelGetValue(lb, p, &vb));
      differ += va != vb;
    }
    check(differ == 0, what + ": label " + name + " differs at " + std::to_string(differ) + " points");
  }
  PetscFunctionReturn(0);
}

// A mesh file read on rank 0 as cells and vertices (its dual graph checked there), distributed without overlap.
PetscErrorCode distributedFile(const char *file, DM *out) {
  DM dm, dist = nullptr;
  PetscFunctionBeginUser;
  PetscCall(DMPlexCreateFromFile(PETSC_COMM_WORLD, file, "test", PETSC_FALSE, &dm));
  PetscInt cStart, cEnd, corners = 0;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  if (cEnd > cStart) PetscCall(DMPlexGetConeSize(dm, cStart, &corners));
  PetscCall(checkDualGraph(dm, corners, file));
  PetscCall(DMPlexDistribute(dm, 0, nullptr, &dist));
  if (dist) {
    PetscCall(DMDestroy(&dm));
    dm = dist;
  }
  *out = dm;
  PetscFunctionReturn(0);
}

// The corners interpolateMesh hands back (tetrahedra only) are every cell's closure vertices, in closure order.
PetscErrorCode checkCorners(DM dm, const std::vector<PetscInt> &corners, bool simplex, const std::string &what) {
  PetscInt cStart, cEnd, vStart, vEnd;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  check(corners.size() == (simplex ? static_cast<std::size_t>(4 * (cEnd - cStart)) : 0u), what + ": corners' count");
  if (!simplex || corners.size() != static_cast<std::size_t>(4 * (cEnd - cStart))) PetscFunctionReturn(0);
  int differ = 0;
  for (PetscInt c = cStart; c < cEnd; ++c) {
    PetscInt n = 0, size, *closure = nullptr;
    std::vector<PetscInt> vertices;
    PetscCall(DMPlexGetTransitiveClosure(dm, c, PETSC_TRUE, &size, &closure));
    for (PetscInt i = 0; i < size; ++i)
      if (closure[2 * i] >= vStart && closure[2 * i] < vEnd) vertices.push_back(closure[2 * i] - vStart), ++n;
    PetscCall(DMPlexRestoreTransitiveClosure(dm, c, PETSC_TRUE, &size, &closure));
    differ += n != 4 || !std::equal(vertices.begin(), vertices.end(), corners.begin() + 4 * (c - cStart));
  }
  check(differ == 0, what + ": " + std::to_string(differ) + " cells' corners not in closure order");
  PetscFunctionReturn(0);
}

PetscErrorCode run(bool simplex, PetscInt n, unsigned seed, const char *file = nullptr) {
  DM dm, ours, petsc;
  PetscFunctionBeginUser;
  const std::string what = file ? std::string(file)
                                : std::string(simplex ? "tetrahedra" : "hexahedra") + " n=" + std::to_string(n) +
                                      " seed=" + std::to_string(seed);
  if (file) PetscCall(distributedFile(file, &dm));
  else PetscCall(distributedBox(simplex, n, seed, &dm));
  std::vector<PetscInt> corners;
  PetscCall(aries::fem::loading::interpolateMesh(dm, &ours, &corners));
  PetscCall(DMPlexInterpolate(dm, &petsc));
  PetscCall(compare(ours, petsc, what));
  PetscCall(checkCorners(ours, corners, simplex, what));
  // the interpolated mesh is valid as PETSc checks it (cones, supports, faces of cells, point SF, interfaces)
  PetscCall(DMPlexCheckSymmetry(ours));
  PetscCall(DMPlexCheckSkeleton(ours, 0));
  PetscCall(DMPlexCheckFaces(ours, 0));
  PetscCall(DMPlexCheckPointSF(ours, nullptr, PETSC_FALSE));
  PetscCall(DMPlexCheckInterfaceCones(ours));
  PetscCall(DMDestroy(&ours));
  PetscCall(DMDestroy(&petsc));
  PetscCall(DMDestroy(&dm));
  PetscFunctionReturn(0);
}

}  // namespace

int main(int argc, char **argv) {
  PetscCall(PetscInitialize(&argc, &argv, nullptr, nullptr));
  for (unsigned seed : {1u, 2u, 3u}) PetscCall(run(true, 4, seed));
  PetscCall(run(true, 1, 4));
  PetscCall(run(false, 3, 1));
  PetscCall(checkIrregularDualGraphs());
  char file[PETSC_MAX_PATH_LEN];
  PetscBool haveFile = PETSC_FALSE;
  PetscCall(PetscOptionsGetString(nullptr, nullptr, "-mesh_file", file, sizeof(file), &haveFile));
  if (haveFile) PetscCall(run(true, 0, 0, file));
  int total = 0;
  PetscCallMPI(MPI_Allreduce(&failures, &total, 1, MPI_INT, MPI_SUM, PETSC_COMM_WORLD));
  PetscCall(PetscPrintf(PETSC_COMM_WORLD, "%s\n", total ? "mesh loading: FAILED" : "mesh loading: all passed"));
  PetscCall(PetscFinalize());
  return total ? 1 : 0;
}
