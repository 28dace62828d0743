// Partitions handed to PETSc's shell partitioner (mesh/mesh_loading.hpp).
#include "mesh/mesh_loading.hpp"
#include "mesh/tuple_numbers.hpp"

#include <metis.h>

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

// METIS's idx_t (Debian: 32 bits) need not be PetscInt's width (64 bits with ARIES_PETSC64): where they differ,
// PETSc's graph is copied into idx_t arrays for METIS (setMetisPartition).

namespace aries::fem::loading {

namespace {

// Hands the shell partitioner this rank's cells grouped by destination: partOf[c] is the part of local cell c.
template <class Part>
PetscErrorCode setShellPartition(PetscPartitioner part, PetscMPIInt size, const std::vector<Part> &partOf) {
  PetscFunctionBeginUser;
  std::vector<PetscInt> sizes(size, 0), points(partOf.size()), start(size, 0);
  for (const Part p : partOf) sizes[p]++;
  for (int p = 1; p < size; ++p) start[p] = start[p - 1] + sizes[p - 1];
  for (size_t c = 0; c < partOf.size(); ++c) points[start[partOf[c]]++] = static_cast<PetscInt>(c);
  PetscCall(PetscPartitionerSetType(part, PETSCPARTITIONERSHELL));
  PetscCall(PetscPartitionerShellSetPartition(part, size, sizes.data(), points.data()));
  PetscFunctionReturn(0);
}

// The face neighbours of tetrahedra (4 corners per cell in `corners`) from their faces' corner triples: the graph
// METIS_MeshToDual makes with 3 common corners, in one pass over the faces where METIS counts the corners every pair of
// cells around a vertex shares (2.1 of the 3.0 s that METIS took on rank 0 for the 1M-tetrahedron box). false (nothing
// made) where a face has more than two cells or two cells have the same corners: METIS's graph is then used.
bool tetrahedronFaceNeighbours(const std::vector<idx_t> &corners, std::vector<idx_t> *offsets,
                               std::vector<idx_t> *adjacency) {
  const std::size_t ne = corners.size() / 4;
  TupleNumbers<3> faces(2 * ne + 16);
  std::vector<std::array<idx_t, 2>> faceCells;  // per face its cells (-1: none yet)
  faceCells.reserve(2 * ne + 16);
  for (std::size_t c = 0; c < ne; ++c)
    for (const auto &f : kTetrahedronFaces) {
      bool inserted;
      const auto id = faces.number(
          sortedTuple<3>({corners[4 * c + f[0]], corners[4 * c + f[1]], corners[4 * c + f[2]]}), &inserted);
      if (inserted) faceCells.push_back({static_cast<idx_t>(c), -1});
      else if (faceCells[id][1] < 0) faceCells[id][1] = static_cast<idx_t>(c);
      else return false;
    }
  offsets->assign(ne + 1, 0);
  for (const auto &fc : faceCells)
    if (fc[1] >= 0) ++(*offsets)[fc[0] + 1], ++(*offsets)[fc[1] + 1];
  for (std::size_t c = 0; c < ne; ++c) (*offsets)[c + 1] += (*offsets)[c];
  adjacency->resize(static_cast<std::size_t>((*offsets)[ne]));
  std::vector<idx_t> next(offsets->begin(), offsets->end() - 1);
  for (const auto &fc : faceCells)
    if (fc[1] >= 0) (*adjacency)[next[fc[0]]++] = fc[1], (*adjacency)[next[fc[1]]++] = fc[0];
  // each cell's neighbours in increasing order, as PETSc's graph of the mesh with faces lists them: the same graph, so
  // the same partition whether the faces are made before or after distribution (-mesh_faces); two cells on the same
  // corners share more than one face, where METIS links them once
  for (std::size_t c = 0; c < ne; ++c) {
    auto row = adjacency->begin();
    std::sort(row + (*offsets)[c], row + (*offsets)[c + 1]);
    if (std::adjacent_find(row + (*offsets)[c], row + (*offsets)[c + 1]) != row + (*offsets)[c + 1]) return false;
  }
  return true;
}

}  // namespace

// The dual graph of the cells of a mesh held as cells and vertices (rank 0 may hold all of it, the others none): cells
// are neighbours when they share as many corners as a face has (3 for tetrahedra, 4 for hexahedra, 2 for
// triangles), each cell's neighbours in increasing order. Tetrahedra by their faces (tetrahedronFaceNeighbours), other
// cells by METIS_MeshToDual.
PetscErrorCode cellDualGraph(DM dm, PetscInt *numCells, std::vector<idx_t> *offsets, std::vector<idx_t> *adjacency) {
  PetscInt cStart, cEnd, vStart, vEnd, dim;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  PetscCall(DMGetDimension(dm, &dim));
  *numCells = cEnd - cStart;
  offsets->assign(1, 0);
  adjacency->clear();
  if (*numCells == 0) PetscFunctionReturn(0);
  std::vector<idx_t> cellStart(1, 0), corners;
  bool tetrahedra = dim == 3;
  for (PetscInt c = cStart; c < cEnd; ++c) {
    PetscInt coneSize;
    const PetscInt *cone;
    PetscCall(DMPlexGetConeSize(dm, c, &coneSize));
    PetscCall(DMPlexGetCone(dm, c, &cone));
    tetrahedra = tetrahedra && coneSize == 4;
    for (PetscInt k = 0; k < coneSize; ++k) corners.push_back(static_cast<idx_t>(cone[k] - vStart));
    cellStart.push_back(static_cast<idx_t>(corners.size()));
  }
  if (!tetrahedra || !tetrahedronFaceNeighbours(corners, offsets, adjacency)) {
    idx_t ne = static_cast<idx_t>(*numCells), nn = static_cast<idx_t>(vEnd - vStart), numbering = 0;
    idx_t common = dim == 3 ? (cellStart[1] == 8 ? 4 : 3) : 2, *xadj = nullptr, *adjncy = nullptr;
    const int status = METIS_MeshToDual(&ne, &nn, cellStart.data(), corners.data(), &common, &numbering, &xadj,
                                        &adjncy);
    PetscCheck(status == METIS_OK, PETSC_COMM_SELF, PETSC_ERR_LIB, "METIS_MeshToDual failed (status %d)", status);
    offsets->assign(xadj, xadj + ne + 1);
    adjacency->assign(adjncy, adjncy + xadj[ne]);
    METIS_Free(xadj);
    METIS_Free(adjncy);
    for (PetscInt c = 0; c < *numCells; ++c)  // in increasing order, as tetrahedronFaceNeighbours lists them
      std::sort(adjacency->begin() + (*offsets)[c], adjacency->begin() + (*offsets)[c + 1]);
  }
  PetscFunctionReturn(0);
}

// METIS k-way partition of the serial mesh's dual graph on rank 0, handed to the shell partitioner.
PetscErrorCode setMetisPartition(DM dm, PetscPartitioner part) {
  PetscMPIInt size;
  PetscInt nv = 0, *offsets = nullptr, *adjacency = nullptr;
  IS globalNumbering = nullptr;
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscInt depth;
  PetscCall(DMPlexGetDepth(dm, &depth));
  std::vector<idx_t> dualOffsets, dualAdjacency;  // for a mesh of cells and vertices only
  if (depth > 1) {
    PetscCall(DMPlexCreatePartitionerGraph(dm, 0, &nv, &offsets, &adjacency, &globalNumbering));
  } else {
    // No faces (mesh/mesh_facets.cpp): the dual graph from the corners, cells sharing a face's number of corners
    // being face neighbours (PETSc's graph of a mesh without faces compares every pair of cells around a vertex).
    PetscCall(cellDualGraph(dm, &nv, &dualOffsets, &dualAdjacency));
  }
  // the graph in METIS's index type: PETSc's own arrays where the widths agree, a copy where they do not
  std::vector<idx_t> partOf(nv, 0), offsetsCopy, adjacencyCopy;
  idx_t *xadj = dualOffsets.data(), *adjncy = dualAdjacency.data();
  if (depth > 1 && nv > 0) {
    if constexpr (sizeof(idx_t) == sizeof(PetscInt)) {
      xadj = reinterpret_cast<idx_t *>(offsets);
      adjncy = reinterpret_cast<idx_t *>(adjacency);
    } else {
      PetscCheck(offsets[nv] <= static_cast<PetscInt>(std::numeric_limits<idx_t>::max()), PETSC_COMM_SELF,
                 PETSC_ERR_SUP,
                 "-partitioner metis: the dual graph has %" PetscInt_FMT " edges, more than METIS's %d-bit indices "
                 "hold (use -partitioner rcb)",
                 offsets[nv], static_cast<int>(8 * sizeof(idx_t)));
      offsetsCopy.assign(offsets, offsets + nv + 1);
      adjacencyCopy.assign(adjacency, adjacency + offsets[nv]);
      xadj = offsetsCopy.data();
      adjncy = adjacencyCopy.data();
    }
  }
  if (nv > 0) {
    idx_t nvtxs = static_cast<idx_t>(nv), ncon = 1, nparts = size, objval = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 42;  // deterministic partitions
    options[METIS_OPTION_NUMBERING] = 0;
    const int status = METIS_PartGraphKway(&nvtxs, &ncon, xadj, adjncy, nullptr, nullptr, nullptr, &nparts,
                                           nullptr, nullptr, options, &objval, partOf.data());
    PetscCheck(status == METIS_OK, comm, PETSC_ERR_LIB, "METIS_PartGraphKway failed (status %d)", status);
  }
  PetscCall(setShellPartition(part, size, partOf));
  PetscCall(PetscFree(offsets));
  PetscCall(PetscFree(adjacency));
  PetscCall(ISDestroy(&globalNumbering));
  PetscFunctionReturn(0);
}

// Recursive coordinate bisection of the cells by their centroids, computed where the cells are (the mesh may be
// spread over the ranks, as an HDF5 mesh is after loading): every group of cells bound for the parts [lo, hi) is cut
// across its longest side at the coordinate that sends the share (hi - lo) / 2 / (hi - lo) of its cells to the first
// half (bisection on the cut value, one reduction of all groups' counts per iteration), until every group is one part.
// The result depends on the centroids only, not on how the cells were spread when loaded, so it is deterministic (unlike
// PT-Scotch's) and needs no rank to hold the whole graph (unlike METIS here, Debian's PETSc having no ParMETIS).
PetscErrorCode setRcbPartition(DM dm, PetscPartitioner part) {
  MPI_Comm comm;
  PetscMPIInt size;
  PetscInt cStart, cEnd;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)dm, &comm));
  PetscCallMPI(MPI_Comm_size(comm, &size));
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  const PetscInt n = cEnd - cStart;
  std::vector<double> centroid(3 * n, 0.0);
  {
    Vec coords;
    PetscSection section;
    PetscInt cdim;
    const PetscScalar *x;
    PetscCall(DMGetCoordinatesLocal(dm, &coords));
    PetscCall(DMGetCoordinateSection(dm, &section));
    PetscCall(DMGetCoordinateDim(dm, &cdim));
    PetscCall(VecGetArrayRead(coords, &x));
    PetscInt vStart, vEnd;
    PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
    for (PetscInt c = cStart; c < cEnd; ++c) {
      PetscInt nc, *closure = nullptr, count = 0;
      PetscCall(DMPlexGetTransitiveClosure(dm, c, PETSC_TRUE, &nc, &closure));
      for (PetscInt k = 0; k < nc; ++k) {
        const PetscInt q = closure[2 * k];
        if (q < vStart || q >= vEnd) continue;
        PetscInt off;
        PetscCall(PetscSectionGetOffset(section, q, &off));
        for (PetscInt d = 0; d < cdim && d < 3; ++d) centroid[3 * (c - cStart) + d] += x[off + d];
        ++count;
      }
      PetscCall(DMPlexRestoreTransitiveClosure(dm, c, PETSC_TRUE, &nc, &closure));
      for (int d = 0; d < 3; ++d) centroid[3 * (c - cStart) + d] /= std::max<PetscInt>(count, 1);
    }
    PetscCall(VecRestoreArrayRead(coords, &x));
  }
  std::vector<int> lo(n, 0), hi(n, size);  // each cell's range of parts; groups are named by lo
  for (;;) {
    std::vector<double> boxLo(3 * size, PETSC_MAX_REAL), boxHi(3 * size, -PETSC_MAX_REAL);
    std::vector<long long> total(size, 0);
    for (PetscInt c = 0; c < n; ++c) {
      if (hi[c] - lo[c] < 2) continue;
      ++total[lo[c]];
      for (int d = 0; d < 3; ++d) {
        boxLo[3 * lo[c] + d] = std::min(boxLo[3 * lo[c] + d], centroid[3 * c + d]);
        boxHi[3 * lo[c] + d] = std::max(boxHi[3 * lo[c] + d], centroid[3 * c + d]);
      }
    }
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, boxLo.data(), 3 * size, MPI_DOUBLE, MPI_MIN, comm));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, boxHi.data(), 3 * size, MPI_DOUBLE, MPI_MAX, comm));
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, total.data(), size, MPI_LONG_LONG, MPI_SUM, comm));
    long long active = 0;
    for (long long t : total) active += t;
    if (active == 0) break;
    // per group: the axis, the target count of the first half, the bracket of the cut value
    std::vector<int> axis(size, 0), span(size, 0);
    std::vector<long long> target(size, 0);
    std::vector<double> cutLo(size, 0.0), cutHi(size, 0.0);
    for (PetscInt c = 0; c < n; ++c) span[lo[c]] = hi[c] - lo[c];  // the same for every cell of a group
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, span.data(), size, MPI_INT, MPI_MAX, comm));
    for (int g = 0; g < size; ++g) {
      if (total[g] == 0) continue;
      for (int d = 1; d < 3; ++d)
        if (boxHi[3 * g + d] - boxLo[3 * g + d] > boxHi[3 * g + axis[g]] - boxLo[3 * g + axis[g]]) axis[g] = d;
      const int half = span[g] / 2;
      target[g] = (total[g] * half + span[g] / 2) / span[g];
      cutLo[g] = boxLo[3 * g + axis[g]];
      cutHi[g] = boxHi[3 * g + axis[g]];
    }
    // the smallest cut with at least `target` cells at or below it (60 halvings: below the coordinates' round-off)
    std::vector<long long> below(size);
    for (int it = 0; it < 60; ++it) {
      std::fill(below.begin(), below.end(), 0);
      for (PetscInt c = 0; c < n; ++c) {
        const int g = lo[c];
        if (hi[c] - lo[c] >= 2 && centroid[3 * c + axis[g]] <= 0.5 * (cutLo[g] + cutHi[g])) ++below[g];
      }
      PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, below.data(), size, MPI_LONG_LONG, MPI_SUM, comm));
      for (int g = 0; g < size; ++g) {
        if (total[g] == 0) continue;
        const double mid = 0.5 * (cutLo[g] + cutHi[g]);
        (below[g] >= target[g] ? cutHi[g] : cutLo[g]) = mid;
      }
    }
    for (PetscInt c = 0; c < n; ++c) {
      const int g = lo[c];
      if (hi[c] - lo[c] < 2) continue;
      const int half = span[g] / 2;
      if (centroid[3 * c + axis[g]] <= cutHi[g]) hi[c] = lo[c] + half;
      else lo[c] += half;
    }
  }
  PetscCall(setShellPartition(part, size, lo));  // each group is one part now: lo is the cell's part
  PetscFunctionReturn(0);
}

}  // namespace aries::fem::loading
