// The faces and edges of a tetrahedral mesh of cells and vertices (mesh/mesh_loading.hpp: interpolateMesh), made in one
// pass over its cells with open-addressing tables of sorted vertex tuples. PETSc 3.18's DMPlexInterpolate makes the
// same mesh in two passes (faces of the cells, then edges of the faces), each building a DM point by point through
// its hash of 4-tuples and its cell-type label: 7.0 of the 17.0 s setup of a 1M-tetrahedron box on 2 ranks
// (-log_view, event DMPlexInterp). The result here is the same DM point for point: the points numbered as PETSc
// numbers them (cells, vertices, then the faces in the order of their first cell, the edges in the order of their first
// face), the same cones and orientations (DMPolytopeGetVertexOrientation, as PETSc computes them), the same point SF
// (PETSc's DMPlexInterpolatePointSF, on the faces' DM and then on the whole one, as DMPlexInterpolate calls it) and the
// same interface orientation, coordinates and labels (tests/mesh/test_loading.cpp compares the two on 1-3 ranks).
// Any other mesh (hexahedra, triangles, overlap, already interpolated) goes to DMPlexInterpolate.
#include "mesh/mesh_loading.hpp"
#include "mesh/tuple_numbers.hpp"

#include <petscdmplex.h>
#include <petscsf.h>

#include <algorithm>
#include <array>
#include <vector>

// PETSc 3.18 exports it (PETSC_EXTERN in its private dmpleximpl.h) and DMPlexInterpolate calls it last: shared faces
// and edges get the same cone on every rank.
extern "C" PetscErrorCode DMPlexOrientInterface_Internal(DM);

namespace aries::fem::loading {

namespace {

// The connectivity of the faces and edges: every cell's faces (point offsets from the first face) with their
// orientations, every face's vertices (from its first cell) and edges with their orientations, every edge's vertices
// (from its first face).
struct TetFacets {
  std::vector<PetscInt> cellFace, cellFaceOrnt;  // 4 per cell
  std::vector<std::array<PetscInt, 3>> faceVertices;
  std::vector<PetscInt> faceEdge, faceEdgeOrnt;  // 3 per face
  std::vector<std::array<PetscInt, 2>> edgeVertices;
};

PetscErrorCode numberFacets(DM dm, PetscInt cStart, PetscInt cEnd, TetFacets *t) {
  PetscFunctionBeginUser;
  const PetscInt nc = cEnd - cStart;
  TupleNumbers<3> faces(static_cast<std::size_t>(2 * nc + 16));
  t->cellFace.resize(static_cast<std::size_t>(4 * nc));
  t->cellFaceOrnt.resize(static_cast<std::size_t>(4 * nc));
  t->faceVertices.reserve(static_cast<std::size_t>(2 * nc + 16));
  for (PetscInt c = cStart; c < cEnd; ++c) {
    const PetscInt *cone;
    PetscCall(DMPlexGetCone(dm, c, &cone));
    for (int f = 0; f < 4; ++f) {
      const int *face = kTetrahedronFaces[f];
      const std::array<PetscInt, 3> raw = {cone[face[0]], cone[face[1]], cone[face[2]]};
      bool inserted;
      const PetscInt id = faces.number(sortedTuple(raw), &inserted);
      PetscInt ornt = 0;
      if (inserted) t->faceVertices.push_back(raw);
      else
        PetscCall(DMPolytopeGetVertexOrientation(DM_POLYTOPE_TRIANGLE, t->faceVertices[id].data(), raw.data(), &ornt));
      t->cellFace[4 * (c - cStart) + f] = id;
      t->cellFaceOrnt[4 * (c - cStart) + f] = ornt;
    }
  }
  const std::size_t nf = t->faceVertices.size();
  TupleNumbers<2> edges(nf + 16);
  t->faceEdge.resize(3 * nf);
  t->faceEdgeOrnt.resize(3 * nf);
  for (std::size_t f = 0; f < nf; ++f) {
    const auto &v = t->faceVertices[f];
    for (int e = 0; e < 3; ++e) {
      const std::array<PetscInt, 2> raw = {v[e], v[(e + 1) % 3]};
      bool inserted;
      const PetscInt id = edges.number(sortedTuple(raw), &inserted);
      PetscInt ornt = 0;
      if (inserted) t->edgeVertices.push_back(raw);
      else PetscCall(DMPolytopeGetVertexOrientation(DM_POLYTOPE_SEGMENT, t->edgeVertices[id].data(), raw.data(), &ornt));
      t->faceEdge[3 * f + e] = id;
      t->faceEdgeOrnt[3 * f + e] = ornt;
    }
  }
  PetscFunctionReturn(0);
}

// A cell-type label stratum over the points [start, end).
PetscErrorCode setTypeStratum(DMLabel label, DMPolytopeType type, PetscInt start, PetscInt end) {
  IS points;
  PetscFunctionBeginUser;
  if (end <= start) PetscFunctionReturn(0);
  PetscCall(ISCreateStride(PETSC_COMM_SELF, end - start, start, 1, &points));
  PetscCall(DMLabelSetStratumIS(label, type, points));
  PetscCall(ISDestroy(&points));
  PetscFunctionReturn(0);
}

// The DM of the cells, vertices and faces (withEdges false: each face's cone its vertices, as PETSc's first pass makes
// it) or of all four (faces' cones their edges). Points: cells [0, nc), vertices [nc, nc + nv), faces, edges.
PetscErrorCode buildDM(DM dm, const TetFacets &t, PetscInt nc, PetscInt nv, bool withEdges, DM *out) {
  DM idm;
  DMLabel types;
  PetscFunctionBeginUser;
  const PetscInt nf = static_cast<PetscInt>(t.faceVertices.size());
  const PetscInt ne = withEdges ? static_cast<PetscInt>(t.edgeVertices.size()) : 0;
  const PetscInt fStart = nc + nv, eStart = fStart + nf, pEnd = eStart + ne;
  PetscCall(DMCreate(PetscObjectComm((PetscObject)dm), &idm));
  PetscCall(DMSetType(idm, DMPLEX));
  PetscCall(DMSetDimension(idm, 3));
  PetscCall(DMPlexSetChart(idm, 0, pEnd));
  for (PetscInt c = 0; c < nc; ++c) PetscCall(DMPlexSetConeSize(idm, c, 4));
  for (PetscInt f = fStart; f < eStart; ++f) PetscCall(DMPlexSetConeSize(idm, f, 3));
  for (PetscInt e = eStart; e < pEnd; ++e) PetscCall(DMPlexSetConeSize(idm, e, 2));
  // made before any cell type is asked for, so PETSc does not compute the types itself
  PetscCall(DMCreateLabel(idm, "celltype"));
  PetscCall(DMPlexGetCellTypeLabel(idm, &types));
  PetscCall(setTypeStratum(types, DM_POLYTOPE_TETRAHEDRON, 0, nc));
  PetscCall(setTypeStratum(types, DM_POLYTOPE_POINT, nc, fStart));
  PetscCall(setTypeStratum(types, DM_POLYTOPE_TRIANGLE, fStart, eStart));
  PetscCall(setTypeStratum(types, DM_POLYTOPE_SEGMENT, eStart, pEnd));
  PetscCall(DMSetUp(idm));
  PetscSection coneSection;
  PetscInt *cones, *ornts;
  PetscCall(DMPlexGetConeSection(idm, &coneSection));
  PetscCall(DMPlexGetCones(idm, &cones));
  PetscCall(DMPlexGetConeOrientations(idm, &ornts));
  auto setCone = [&](PetscInt p, const PetscInt *points, const PetscInt *orientations, PetscInt n) -> PetscErrorCode {
    PetscInt off;
    PetscFunctionBeginUser;
    PetscCall(PetscSectionGetOffset(coneSection, p, &off));
    for (PetscInt k = 0; k < n; ++k) {
      cones[off + k] = points[k];
      ornts[off + k] = orientations ? orientations[k] : 0;
    }
    PetscFunctionReturn(0);
  };
  for (PetscInt c = 0; c < nc; ++c) {
    PetscInt faces[4];
    for (int f = 0; f < 4; ++f) faces[f] = fStart + t.cellFace[4 * c + f];
    PetscCall(setCone(c, faces, &t.cellFaceOrnt[4 * c], 4));
  }
  for (PetscInt f = 0; f < nf; ++f) {
    if (withEdges) {
      PetscInt edges[3];
      for (int e = 0; e < 3; ++e) edges[e] = eStart + t.faceEdge[3 * f + e];
      PetscCall(setCone(fStart + f, edges, &t.faceEdgeOrnt[3 * f], 3));
    } else {
      PetscCall(setCone(fStart + f, t.faceVertices[f].data(), nullptr, 3));
    }
  }
  for (PetscInt e = 0; e < ne; ++e) PetscCall(setCone(eStart + e, t.edgeVertices[e].data(), nullptr, 2));
  PetscCall(DMPlexSymmetrize(idm));
  PetscCall(DMPlexStratify(idm));
  *out = idm;
  PetscFunctionReturn(0);
}

// Whether the fast path applies: a 3D mesh of tetrahedra only, cells and vertices (cells first, then the vertices),
// not overlapped. Collective (every rank must take the same path: PETSc's point SF calls are collective).
PetscErrorCode fastPathApplies(DM dm, bool *applies) {
  PetscInt dim, depth, pStart, pEnd, cStart, cEnd, vStart, vEnd, overlap, tets = 0;
  PetscFunctionBeginUser;
  PetscCall(DMGetDimension(dm, &dim));
  PetscCall(DMPlexGetDepth(dm, &depth));
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  PetscCall(DMPlexGetOverlap(dm, &overlap));
  bool ok = dim == 3 && depth == 1 && pStart == 0 && cStart == 0 && vStart == cEnd && vEnd == pEnd && overlap == 0;
  if (ok && cEnd > 0) {
    DMLabel types;
    PetscCall(DMPlexGetCellTypeLabel(dm, &types));
    PetscCall(DMLabelGetStratumSize(types, DM_POLYTOPE_TETRAHEDRON, &tets));
    ok = tets == cEnd;
  }
  int local = ok ? 1 : 0, all = 0;
  PetscCallMPI(MPI_Allreduce(&local, &all, 1, MPI_INT, MPI_MIN, PetscObjectComm((PetscObject)dm)));
  *applies = all == 1;
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode interpolateMesh(DM dm, DM *interpolated, std::vector<PetscInt> *corners) {
  bool fast = false;
  PetscFunctionBeginUser;
  if (corners) corners->clear();
  PetscCall(fastPathApplies(dm, &fast));
  if (!fast) {
    PetscCall(DMPlexInterpolate(dm, interpolated));
    PetscFunctionReturn(0);
  }
  PetscInt cEnd, vEnd;
  PetscCall(DMPlexGetHeightStratum(dm, 0, nullptr, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, nullptr, &vEnd));
  TetFacets facets;
  PetscCall(numberFacets(dm, 0, cEnd, &facets));
  if (corners) {  // a tetrahedron's closure lists its corners in its cone's order (PETSc's faces keep the first
                  // face's vertices and orientations relative to it; tests/mesh/test_loading.cpp checks it)
    corners->resize(static_cast<std::size_t>(4 * cEnd));
    for (PetscInt c = 0; c < cEnd; ++c) {
      const PetscInt *cone;
      PetscCall(DMPlexGetCone(dm, c, &cone));
      for (int k = 0; k < 4; ++k) (*corners)[4 * c + k] = cone[k] - cEnd;  // vertices start at cEnd
    }
  }
  PetscSF pointSF;
  PetscInt roots;
  PetscCall(DMGetPointSF(dm, &pointSF));
  PetscCall(PetscSFGetGraph(pointSF, &roots, nullptr, nullptr, nullptr));
  PetscSF facesSF = nullptr;  // the point SF with the shared faces (PETSc's first pass), for the edges' pass
  if (roots >= 0) {
    DM withFaces;
    PetscCall(buildDM(dm, facets, cEnd, vEnd - cEnd, false, &withFaces));
    PetscCall(DMPlexInterpolatePointSF(withFaces, pointSF));
    PetscCall(DMGetPointSF(withFaces, &facesSF));
    PetscCall(PetscObjectReference((PetscObject)facesSF));
    PetscCall(DMDestroy(&withFaces));
  }
  DM idm;
  PetscCall(buildDM(dm, facets, cEnd, vEnd - cEnd, true, &idm));
  if (facesSF) {
    PetscCall(DMPlexInterpolatePointSF(idm, facesSF));
    PetscCall(PetscSFDestroy(&facesSF));
  }
  // the rest of DMPlexInterpolate: name, coordinates, labels, shared faces and edges oriented alike on every rank
  // (always: aries does not read PETSc's -dm_plex_interpolate_orient_interfaces), and what DMPlexCopy_Internal copies
  const char *name;
  PetscCall(PetscObjectGetName((PetscObject)dm, &name));
  PetscCall(PetscObjectSetName((PetscObject)idm, name));
  PetscCall(DMPlexCopyCoordinates(dm, idm));
  PetscCall(DMCopyLabels(dm, idm, PETSC_COPY_VALUES, PETSC_FALSE, DM_COPY_LABELS_FAIL));
  PetscCall(DMPlexOrientInterface_Internal(idm));  // PETSc's default (-dm_plex_interpolate_orient_interfaces true)
  const PetscReal *maxCell, *lStart, *l;
  PetscCall(DMGetPeriodicity(dm, &maxCell, &lStart, &l));
  PetscCall(DMSetPeriodicity(idm, maxCell, lStart, l));
  PetscBool distribute;
  DMPlexReorderDefaultFlag reorder;
  PetscCall(DMPlexDistributeGetDefault(dm, &distribute));
  PetscCall(DMPlexDistributeSetDefault(idm, distribute));
  PetscCall(DMPlexReorderGetDefault(dm, &reorder));
  PetscCall(DMPlexReorderSetDefault(idm, reorder));
  *interpolated = idm;
  PetscFunctionReturn(0);
}

}  // namespace aries::fem::loading
