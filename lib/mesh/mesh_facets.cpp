// The faces and edges of a 3D mesh made where the mesh lives (mesh/mesh_loading.hpp): PETSc 3.18 interpolates a gmsh
// mesh on rank 0 (DMPlexCreateGmsh: 13 s of a 1M-tetrahedron box's 29 s setup on 2 ranks) and labels its tagged faces
// there. A 3D mesh is instead read as cells and vertices, distributed, and interpolated by every rank for its part;
// its tagged faces (read from the file by the structural check, mesh/gmsh_check.hpp) become label rows on rank 0, one
// per (face, cell containing it), which travel with their cells when the mesh is distributed, and every rank labels
// its copies from the rows of its cells ("Face Sets", as PETSc's reader makes them). An HDF5 mesh's face and edge
// label rows (mesh_hdf5.cpp) take the same way from the rank whose block of the file holds their cell.
#include "mesh/mesh_loading.hpp"

#include "core/errors.hpp"
#include "core/parallel.hpp"

#include <petscsf.h>

#include <algorithm>
#include <unordered_map>

namespace aries::fem::loading {

namespace {

// Rank 0: the label rows (kPointLabelCols) of the file's tagged faces on the serial mesh read without them, one per
// (face, cell containing it), in natural ids. numberingMatches is false (and the rows empty) where the serial mesh's
// vertices are not numbered as GmshFacets assumes (checked by count and coordinates). Collective; a tagged face that
// is no face of a cell is a one-line error.
PetscErrorCode gmshFacetRows(MPI_Comm comm, const Mesh &mesh, DM serial, const GmshFacets &facets,
                             std::vector<long long> *rows, bool *numberingMatches) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  rows->clear();
  bool matches = true;
  std::string unmatched;  // a tagged face that is no face of any cell
  if (rank == 0) {
    PetscInt cStart, cEnd, vStart, vEnd, cdim;
    PetscCall(DMPlexGetHeightStratum(serial, 0, &cStart, &cEnd));
    PetscCall(DMPlexGetDepthStratum(serial, 0, &vStart, &vEnd));
    PetscCall(DMGetCoordinateDim(serial, &cdim));
    matches = vEnd - vStart == facets.numVertices;
    Vec coordinates;
    PetscSection section;
    const PetscScalar *x;
    PetscCall(DMGetCoordinatesLocal(serial, &coordinates));
    PetscCall(DMGetCoordinateSection(serial, &section));
    PetscCall(VecGetArrayRead(coordinates, &x));
    for (size_t i = 0; i < facets.facets.size() && matches && unmatched.empty(); ++i) {
      const GmshFacets::Facet &f = facets.facets[i];
      std::array<PetscInt, 4> corners{};
      for (int k = 0; k < f.numCorners && matches; ++k) {
        corners[k] = vStart + static_cast<PetscInt>(f.vertex[k]);
        PetscInt off;
        PetscCall(PetscSectionGetOffset(section, corners[k], &off));
        for (PetscInt d = 0; d < cdim; ++d) matches = matches && x[off + d] == f.corner[3 * k + d];
      }
      if (!matches) break;
      std::array<long long, 3> sorted = {-1, -1, -1};
      {
        std::array<long long, 4> ids = {-1, -1, -1, -1};
        const int n = std::clamp(f.numCorners, 0, 4);
        for (int k = 0; k < n; ++k) ids[k] = f.vertex[k];
        std::sort(ids.begin(), ids.begin() + n);
        for (int k = 0; k < std::min(3, n); ++k) sorted[k] = ids[k];
      }
      // the cells whose corners include all of the face's: the support of its first corner, filtered
      PetscInt supportSize;
      const PetscInt *support;
      PetscCall(DMPlexGetSupportSize(serial, corners[0], &supportSize));
      PetscCall(DMPlexGetSupport(serial, corners[0], &support));
      bool found = false;
      for (PetscInt s = 0; s < supportSize; ++s) {
        PetscInt coneSize;
        const PetscInt *cone;
        PetscCall(DMPlexGetConeSize(serial, support[s], &coneSize));
        PetscCall(DMPlexGetCone(serial, support[s], &cone));
        bool all = true;
        for (int k = 1; k < f.numCorners && all; ++k) all = std::find(cone, cone + coneSize, corners[k]) != cone + coneSize;
        if (!all) continue;
        found = true;
        rows->insert(rows->end(), {static_cast<long long>(support[s] - cStart), f.dim, f.tag, sorted[0], sorted[1],
                                   sorted[2]});
      }
      if (!found) {
        char where[160];
        std::snprintf(where, sizeof(where), "at (%g, %g, %g)", f.corner[0], f.corner[1], f.corner[2]);
        unmatched = "a face of physical group " + std::to_string(f.tag) + " (corner " + where + ")";
      }
    }
    PetscCall(VecRestoreArrayRead(coordinates, &x));
  }
  PetscCall(core::collectiveCheck(comm, !unmatched.empty(),
                                  "mesh '" + mesh.filename + "' (" + mesh.fileOption + "): " + unmatched +
                                      " is not a face of any cell"));
  int ok = matches ? 1 : 0;
  PetscCallMPI(MPI_Bcast(&ok, 1, MPI_INT, 0, comm));
  *numberingMatches = ok != 0;
  if (!*numberingMatches) rows->clear();
  PetscFunctionReturn(0);
}

// PETSc's gmsh reader with second-order elements read as their corners: its high-order coordinate field (its default)
// would give the mesh coordinates no vertex layout; -element p2 places the edge nodes from the file itself
// (mesh_quadratic.cpp). The option is set for this reading only, unless the user gave it (true is refused).
PetscErrorCode readAsCorners(MPI_Comm comm, const std::string &file, PetscBool interpolate, DM *serial) {
  PetscBool highOrder = PETSC_FALSE, highOrderSet = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsGetBool(nullptr, nullptr, "-dm_plex_gmsh_highorder", &highOrder, &highOrderSet));
  if (highOrderSet && highOrder)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -dm_plex_gmsh_highorder: aries reads a second-order gmsh mesh as its corners, and -element p2 "
            "takes the edge nodes from the file itself; remove the option");
  if (!highOrderSet) PetscCall(PetscOptionsSetValue(nullptr, "-dm_plex_gmsh_highorder", "false"));
  const PetscErrorCode ierr = DMPlexCreateFromFile(comm, file.c_str(), "aries", interpolate, serial);
  if (!highOrderSet) PetscCall(PetscOptionsClearValue(nullptr, "-dm_plex_gmsh_highorder"));
  PetscCall(ierr);
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode readGmshSerial(MPI_Comm comm, const Mesh &mesh, const GmshFacets &facets, bool mayDeferFaces,
                              DM *serial, bool *deferred, std::vector<long long> *facetRows) {
  PetscFunctionBeginUser;
  // A 3D mesh whose tagged faces the check read, labelled as PETSc labels them by default (any other -dm_plex_gmsh_
  // label or geometry option keeps PETSc's own reading).
  int defer = mayDeferFaces && facets.known && facets.cellDim == 3 ? 1 : 0;
  for (const char *petscOption : {"-dm_plex_gmsh_use_regions", "-dm_plex_gmsh_use_generic", "-dm_plex_gmsh_multiple_tags",
                                  "-dm_plex_gmsh_periodic", "-dm_plex_gmsh_hybrid", "-dm_plex_gmsh_highorder",
                                  "-dm_plex_gmsh_project", "-dm_localize_height"}) {
    PetscBool set = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(nullptr, nullptr, petscOption, &set));
    if (set) defer = 0;
  }
  PetscCallMPI(MPI_Bcast(&defer, 1, MPI_INT, 0, comm));
  PetscCall(readAsCorners(comm, mesh.filename, defer ? PETSC_FALSE : PETSC_TRUE, serial));
  if (defer) {
    bool numberingMatches = false;
    PetscCall(gmshFacetRows(comm, mesh, *serial, facets, facetRows, &numberingMatches));
    if (!numberingMatches) {  // PETSc numbered the vertices otherwise: its own reading
      PetscCall(PetscInfo(nullptr, "aries: %s: vertex numbering not as expected; faces made on rank 0\n",
                          mesh.filename.c_str()));
      PetscCall(DMDestroy(serial));
      PetscCall(readAsCorners(comm, mesh.filename, PETSC_TRUE, serial));
      defer = 0;
    }
  }
  *deferred = defer != 0;
  PetscFunctionReturn(0);
}

PetscErrorCode routeDeferredRows(MPI_Comm comm, PetscSF migration, DM loaded, const std::vector<PetscInt> &loadedNatural,
                                 DeferredLabelRows *deferred) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  if (!migration) PetscFunctionReturn(0);  // one rank: the cells stay where they were read
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  // The rank each loaded cell went to: every distributed point tells its root (overlap 0: one rank per cell).
  PetscInt nroots, nleaves, minLeaf, maxLeaf, pStart, pEnd, cStart, cEnd;
  PetscCall(PetscSFGetGraph(migration, &nroots, &nleaves, nullptr, nullptr));
  PetscCall(PetscSFGetLeafRange(migration, &minLeaf, &maxLeaf));
  std::vector<int> leafRank(std::max<PetscInt>(maxLeaf + 1, 0), rank), rootRank(std::max<PetscInt>(nroots, 0), -1);
  PetscCall(PetscSFReduceBegin(migration, MPI_INT, leafRank.data(), rootRank.data(), MPI_MAX));
  PetscCall(PetscSFReduceEnd(migration, MPI_INT, leafRank.data(), rootRank.data(), MPI_MAX));
  PetscCall(DMPlexGetChart(loaded, &pStart, &pEnd));
  PetscCall(DMPlexGetHeightStratum(loaded, 0, &cStart, &cEnd));
  std::unordered_map<PetscInt, PetscInt> loadedCell;  // natural id -> loaded cell, for the rows' cells only
  for (const std::vector<long long> &rows : deferred->rows)
    for (size_t r = 0; r < rows.size(); r += kPointLabelCols) loadedCell.emplace(static_cast<PetscInt>(rows[r]), -1);
  for (PetscInt c = cStart; c < cEnd && !loadedCell.empty(); ++c) {
    const auto it = loadedCell.find(loadedNatural[c - pStart]);
    if (it != loadedCell.end()) it->second = c;
  }
  bool ok = true;
  for (std::vector<long long> &rows : deferred->rows) {
    std::vector<int> dest(rows.size() / kPointLabelCols, 0);
    for (size_t r = 0; r < dest.size(); ++r) {
      const PetscInt c = loadedCell[static_cast<PetscInt>(rows[r * kPointLabelCols])];
      const int to = c >= 0 && c - pStart < nroots ? rootRank[c - pStart] : -1;
      ok = ok && to >= 0;
      dest[r] = std::max(to, 0);
    }
    core::RowRoute route;
    std::vector<long long> received;
    PetscCall(route.setup(comm, dest));
    PetscCall(route.forward(rows, kPointLabelCols, &received));
    rows = std::move(received);
  }
  PetscCall(core::collectiveCheck(comm, !ok, "a labelled face's cell was not distributed (an aries bug; "
                                             "-mesh_faces serial avoids it)"));
  PetscFunctionReturn(0);
}

PetscErrorCode labelDeferredRows(MPI_Comm comm, Mesh *mesh, const DeferredLabelRows &deferred) {
  PetscFunctionBeginUser;
  std::unordered_map<PetscInt, PetscInt> localCell;  // natural id -> index among the local cells
  localCell.reserve(mesh->naturalCell.size());
  for (size_t c = 0; c < mesh->naturalCell.size(); ++c) localCell.emplace(mesh->naturalCell[c], static_cast<PetscInt>(c));
  bool ok = true;
  for (size_t k = 0; k < deferred.names.size(); ++k) {
    const std::vector<long long> &rows = deferred.rows[k];
    long long count = static_cast<long long>(rows.size());
    PetscCallMPI(MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_LONG_LONG, MPI_SUM, comm));
    if (count == 0) continue;  // as PETSc's reader: no label for a file without such rows
    std::vector<long long> mine(rows);  // the cells as local indices
    for (size_t r = 0; r < mine.size(); r += kPointLabelCols) {
      const auto it = localCell.find(static_cast<PetscInt>(mine[r]));
      ok = ok && it != localCell.end();
      mine[r] = it != localCell.end() ? it->second : -1;
    }
    DMLabel label;
    PetscCall(DMCreateLabel(mesh->dm, deferred.names[k].c_str()));
    PetscCall(DMGetLabel(mesh->dm, deferred.names[k].c_str(), &label));
    PetscCall(applyLabelRows(mesh->dm, label, mine, kPointLabelCols, 0, mesh->naturalVertex.data(), &ok));
  }
  PetscCall(core::collectiveCheck(comm, !ok, "mesh '" + mesh->filename + "': a labelled face was lost when the "
                                             "mesh was distributed (an aries bug; -mesh_faces serial avoids it)"));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem::loading
