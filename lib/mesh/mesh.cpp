#include "mesh/mesh.hpp"

#include "mesh/gmsh_check.hpp"
#include "core/errors.hpp"
#include "core/options.hpp"
#include "mesh/mesh_options.hpp"

#include "mesh/mesh_loading.hpp"

#include <petscsf.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <numeric>
#include <set>
#include <sstream>


namespace aries::fem {

using core::sharedLeafPoints;

Mesh::~Mesh() {
  if (dm) DMDestroy(&dm);
}

namespace loading {

// "dim tag name" lines of a gmsh file's $PhysicalNames (MSH 2 and 4 share the section format); rank 0 reads.
std::string physicalNamesBlob(const std::string &file) {
  std::string blob;
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("$PhysicalNames", 0) == 0) {
      int n = 0;
      if (!(in >> n)) break;
      for (int i = 0; i < n; ++i) {
        int dim, tag;
        std::string name;
        if (!(in >> dim >> tag)) break;
        std::getline(in, name);
        const auto a = name.find('"'), b = name.rfind('"');
        if (a != std::string::npos && b > a)
          blob += std::to_string(dim) + " " + std::to_string(tag) + " " + name.substr(a + 1, b - a - 1) + "\n";
      }
      break;
    }
    if (line.rfind("$Nodes", 0) == 0) break;  // names come before nodes
  }
  return blob;
}

// Rank 0's blob reaches every rank, parsed into tag -> name.
PetscErrorCode parsePhysicalNames(MPI_Comm comm, std::string blob, std::map<std::string, Mesh::PhysicalGroup> *names) {
  PetscFunctionBeginUser;
  int len = static_cast<int>(blob.size());
  PetscCallMPI(MPI_Bcast(&len, 1, MPI_INT, 0, comm));
  blob.resize(len);
  PetscCallMPI(MPI_Bcast(blob.data(), len, MPI_CHAR, 0, comm));
  std::istringstream lines(blob);
  std::string l;
  while (std::getline(lines, l)) {
    std::istringstream fields(l);
    long dim, tag;
    fields >> dim >> tag;
    std::string name;
    std::getline(fields, name);
    (*names)[name.substr(1)] = {static_cast<PetscInt>(dim), static_cast<PetscInt>(tag)};
  }
  PetscFunctionReturn(0);
}

// The element shape from the cell and space dimensions (-uv_map: triangles in 3D with 2D unknowns); a non-flat
// triangle surface about to be read in 2D is an error (PETSc would silently drop z).
PetscErrorCode classifyShape(const GmshFacts &facts, Mesh *mesh) {
  PetscFunctionBeginUser;
  // PETSc reads a triangle mesh in 2D unless told otherwise and silently drops z: a curved surface would run flat.
  PetscBool spaceDimSet = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-dm_plex_gmsh_spacedim", &spaceDimSet));
  if (mesh->topoDim == 2 && mesh->spaceDim == 2 && !spaceDimSet && facts.coordinatesKnown &&
      facts.zRange > 1e-12 * facts.extent) {
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "mesh '%s' is a triangle surface that is not flat (z varies by %g) but would be read in 2D with z dropped: "
            "pass -dm_plex_gmsh_spacedim 3 (cloth, -uv_map), or -dm_plex_gmsh_spacedim 2 to flatten it on purpose",
            mesh->filename.c_str(), facts.zRange);
  }
  PetscBool uvMap = PETSC_FALSE;
  PetscCall(core::get(opt::uvMap, &uvMap));
  if (uvMap && !(mesh->topoDim == 2 && mesh->spaceDim == 3))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -uv_map needs a triangle surface in 3D (mesh '%s' has %d-dimensional cells in %d-dimensional "
            "space; pass -dm_plex_gmsh_spacedim 3)",
            mesh->filename.c_str(), (int)mesh->topoDim, (int)mesh->spaceDim);
  mesh->uvMap = uvMap;
  if (mesh->topoDim == 3 && mesh->spaceDim == 3) mesh->shape = energies::ElementShape::Tet;
  else if (uvMap) mesh->shape = energies::ElementShape::Planar;  // 2D unknowns, rest from the 3D triangles
  else if (mesh->topoDim == 2 && mesh->spaceDim == 3) mesh->shape = energies::ElementShape::Cloth;
  else if (mesh->topoDim == 2 && mesh->spaceDim == 2) mesh->shape = energies::ElementShape::Planar;
  else
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "mesh '%s' has %d-dimensional cells in %d-dimensional space; aries supports tetrahedra in 3D and "
            "triangles in 2D or 3D (for triangles in 3D pass -dm_plex_gmsh_spacedim 3)",
            mesh->filename.c_str(), (int)mesh->topoDim, (int)mesh->spaceDim);
  PetscFunctionReturn(0);
}

// The cells' polytope: all tetrahedra, all triangles, or all hexahedra (mesh->hexahedra); any other cell, or a mix,
// is a one-line error naming the file. Collective (rank 0 may hold every cell).
PetscErrorCode classifyCells(DM dm, Mesh *mesh) {
  PetscFunctionBeginUser;
  PetscInt cStart, cEnd;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  int kinds = 0;  // bit per DMPolytopeType present
  for (PetscInt c = cStart; c < cEnd; ++c) {
    DMPolytopeType type;
    PetscCall(DMPlexGetCellType(dm, c, &type));
    kinds |= 1 << static_cast<int>(type);
  }
  int all = 0;
  PetscCallMPI(MPI_Allreduce(&kinds, &all, 1, MPI_INT, MPI_BOR, PetscObjectComm((PetscObject)dm)));
  const int tet = 1 << DM_POLYTOPE_TETRAHEDRON, tri = 1 << DM_POLYTOPE_TRIANGLE, hex = 1 << DM_POLYTOPE_HEXAHEDRON;
  if (all != tet && all != tri && all != hex) {
    std::string present;
    for (int t = 0; t < DM_NUM_POLYTOPES; ++t)
      if (all & (1 << t)) present += std::string(present.empty() ? "" : ", ") + DMPolytopeTypes[t];
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "mesh '%s' (%s) has cells of type %s; aries needs one cell type: linear tetrahedra, triangles, or "
            "trilinear hexahedra",
            mesh->filename.c_str(), mesh->fileOption.c_str(), present.c_str());
  }
  mesh->hexahedra = all == hex;
  if (mesh->hexahedra && mesh->uvMap)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -uv_map needs a triangle surface (mesh '%s' has hexahedra)",
            mesh->filename.c_str());
  PetscFunctionReturn(0);
}

// Natural ids of the local cells and vertices: `loaded` holds one per point of the chart of the mesh as read (cell id,
// vertex id, edge id for a quadratic mesh, or -1), and the migration SF (leaf: a point of the distributed mesh, root:
// the point it came from; none on one rank) carries them to the distributed mesh (pointNatural: per local point). Cells that are leaves of the point SF belong to another rank
// (overlap layer).
PetscErrorCode numberNaturally(PetscSF migration, const std::vector<PetscInt> &loaded, Mesh *mesh,
                               std::vector<PetscInt> *pointNatural) {
  PetscInt pStart, pEnd;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(mesh->dm, &pStart, &pEnd));
  std::vector<PetscInt> &natural = *pointNatural;
  natural.assign(pEnd - pStart, -1);
  if (migration) {
    PetscCall(PetscSFBcastBegin(migration, MPIU_INT, loaded.data(), natural.data(), MPI_REPLACE));
    PetscCall(PetscSFBcastEnd(migration, MPIU_INT, loaded.data(), natural.data(), MPI_REPLACE));
    PetscCall(PetscSFDestroy(&migration));
  } else {
    natural = loaded;
    natural.resize(pEnd - pStart, -1);  // faces and edges made after loading have no natural id
  }
  mesh->naturalCell.resize(mesh->cEnd - mesh->cStart);
  mesh->naturalVertex.resize(mesh->vEnd - mesh->vStart);
  for (PetscInt c = mesh->cStart; c < mesh->cEnd; ++c) mesh->naturalCell[c - mesh->cStart] = natural[c - pStart];
  for (PetscInt v = mesh->vStart; v < mesh->vEnd; ++v) mesh->naturalVertex[v - mesh->vStart] = natural[v - pStart];
  std::vector<char> leaf;
  PetscCall(sharedLeafPoints(mesh->dm, &leaf));
  mesh->cellOwned.resize(mesh->cEnd - mesh->cStart);
  for (PetscInt c = mesh->cStart; c < mesh->cEnd; ++c) mesh->cellOwned[c - mesh->cStart] = !leaf[c - pStart];
  PetscFunctionReturn(0);
}

// Rest bounding box and its diagonal L.
PetscErrorCode restBoundingBox(MPI_Comm comm, Mesh *mesh) {
  PetscFunctionBeginUser;
  Vec coords;
  PetscInt n;
  const PetscScalar *x;
  PetscCall(DMGetCoordinatesLocal(mesh->dm, &coords));
  PetscCall(VecGetLocalSize(coords, &n));
  PetscCall(VecGetArrayRead(coords, &x));
  double lo[3] = {PETSC_MAX_REAL, PETSC_MAX_REAL, PETSC_MAX_REAL}, hi[3] = {-PETSC_MAX_REAL, -PETSC_MAX_REAL, -PETSC_MAX_REAL};
  if (mesh->spaceDim == 2) lo[2] = hi[2] = 0.0;
  for (PetscInt i = 0; i < n; i += mesh->spaceDim)
    for (int d = 0; d < mesh->spaceDim; ++d) {
      lo[d] = std::min(lo[d], (double)x[i + d]);
      hi[d] = std::max(hi[d], (double)x[i + d]);
    }
  PetscCall(VecRestoreArrayRead(coords, &x));
  double glo[3], ghi[3];
  PetscCallMPI(MPI_Allreduce(lo, glo, 3, MPI_DOUBLE, MPI_MIN, comm));
  PetscCallMPI(MPI_Allreduce(hi, ghi, 3, MPI_DOUBLE, MPI_MAX, comm));
  mesh->boxMin = Eigen::Vector3d(glo[0], glo[1], glo[2]);
  mesh->boxMax = Eigen::Vector3d(ghi[0], ghi[1], ghi[2]);
  mesh->diagonal = (mesh->boxMax - mesh->boxMin).norm();
  if (!(mesh->diagonal > 0.0))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "mesh '%s' has a zero-size bounding box", mesh->filename.c_str());
  PetscFunctionReturn(0);
}

// Natural id of every point of a serial mesh's chart: its cell or vertex number, -1 for faces and edges.
PetscErrorCode serialNaturalIds(DM dm, std::vector<PetscInt> *natural) {
  PetscInt pStart, pEnd, cStart, cEnd, vStart, vEnd;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(dm, &pStart, &pEnd));
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  natural->assign(pEnd - pStart, -1);
  for (PetscInt c = cStart; c < cEnd; ++c) (*natural)[c - pStart] = c - cStart;
  for (PetscInt v = vStart; v < vEnd; ++v) (*natural)[v - pStart] = v - vStart;
  PetscFunctionReturn(0);
}

// The gmsh file, read on rank 0 (the other ranks get an empty mesh): its DM, the natural id of every point, the
// physical names and the global counts.
PetscErrorCode readGmshMesh(MPI_Comm comm, Mesh *mesh, DM *serial, std::vector<PetscInt> *natural, bool mayDeferFaces,
                            bool *deferred, std::vector<long long> *facetRows,
                            std::vector<GmshFacets::EdgeNode> *edgeNodes) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  GmshFacts facts;
  GmshFacets facets;
  PetscCall(validateGmshFile(comm, mesh->filename, &facts, mesh->fileOption,
                             mayDeferFaces || edgeNodes ? &facets : nullptr));
  if (edgeNodes) *edgeNodes = std::move(facets.edgeNodes);
  PetscCall(parsePhysicalNames(comm, rank == 0 ? physicalNamesBlob(mesh->filename) : std::string(),
                               &mesh->physicalNames));
  // Without this PETSc 3.18 drops gmsh point groups (pinned vertex sets) instead of labelling them.
  PetscBool hasMark = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-dm_plex_gmsh_mark_vertices", &hasMark));
  if (!hasMark) PetscCall(PetscOptionsSetValue(nullptr, "-dm_plex_gmsh_mark_vertices", "true"));
  PetscCall(readGmshSerial(comm, *mesh, facets, mayDeferFaces, serial, deferred, facetRows));
  PetscCall(DMGetDimension(*serial, &mesh->topoDim));
  PetscCall(DMGetCoordinateDim(*serial, &mesh->spaceDim));
  {
    PetscErrorCode ierr = classifyShape(facts, mesh);
    if (!ierr) ierr = classifyCells(*serial, mesh);
    if (ierr) PetscCall(DMDestroy(serial));
    PetscCall(ierr);
  }
  PetscCall(serialNaturalIds(*serial, natural));
  PetscInt counts[2] = {0, 0}, cStart, cEnd, vStart, vEnd;
  PetscCall(DMPlexGetHeightStratum(*serial, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(*serial, 0, &vStart, &vEnd));
  counts[0] = vEnd - vStart;
  counts[1] = cEnd - cStart;
  PetscCallMPI(MPI_Bcast(counts, 2, MPIU_INT, 0, comm));
  mesh->numVerticesGlobal = counts[0];
  mesh->numCellsGlobal = counts[1];
  PetscFunctionReturn(0);
}

}  // namespace loading

using namespace loading;

PetscErrorCode loadMesh(MPI_Comm comm, Mesh *mesh, const std::string &file, const char *option) {
  PetscMPIInt size;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  if (file.empty()) PetscCall(core::get(opt::meshFile, &mesh->filename, &set));
  else mesh->filename = file, set = PETSC_TRUE;
  mesh->fileOption = file.empty() ? "-dm_plex_filename" : option;
  if (!set)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "no mesh: give -dm_plex_filename FILE.msh (gmsh format) or FILE.h5 (converted with -mesh_convert)");
  const bool hdf5 = isHdf5Mesh(mesh->filename);
  int partitionerChoice = 0;
  PetscBool partitionerSet = PETSC_FALSE;
  PetscCall(core::getChoice(opt::partitioner, &partitionerChoice, &partitionerSet));
  const std::string partitioner =
      partitionerSet ? core::choices(opt::partitioner)[partitionerChoice] : std::string(hdf5 ? "rcb" : "metis");
  if (hdf5 && partitioner == "metis")
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "option -partitioner metis: METIS partitions the whole mesh on rank 0, but '%s' is read in parallel; use "
            "-partitioner rcb (the default for an HDF5 mesh) or ptscotch, or the gmsh mesh",
            mesh->filename.c_str());

  int facesChoice = 0;
  PetscCall(core::getChoice(opt::meshFaces, &facesChoice));
  int elementChoice = 0;
  PetscCall(core::getChoice(opt::element, &elementChoice));
  // faces made after distribution (-mesh_faces distributed): linear cells, a partitioner that needs no faces
  const bool mayDeferFaces = core::choices(opt::meshFaces)[facesChoice] == std::string("distributed") &&
                             core::choices(opt::element)[elementChoice] == std::string("p1") && partitioner != "ptscotch";

  DM loaded = nullptr;
  std::vector<PetscInt> loadedNatural;  // per point of the loaded mesh's chart
  bool deferredFaces = false;
  DeferredLabelRows deferredRows;  // the labelled faces and edges of a mesh read without them, by the loaded cells
  if (hdf5) PetscCall(readHdf5Mesh(comm, mesh, &loaded, &loadedNatural, mayDeferFaces, &deferredFaces, &deferredRows));
  const bool quadratic = core::choices(opt::element)[elementChoice] == std::string("p2");
  std::vector<GmshFacets::EdgeNode> edgeNodes;  // rank 0: a second-order file's edge nodes, for -element p2
  if (!hdf5) {
    std::vector<long long> facetRows;  // rank 0: the tagged faces of a mesh read without faces
    PetscCall(readGmshMesh(comm, mesh, &loaded, &loadedNatural, mayDeferFaces, &deferredFaces, &facetRows,
                           quadratic ? &edgeNodes : nullptr));
    if (deferredFaces) deferredRows = {{"Face Sets"}, {std::move(facetRows)}};
  }
  PetscInt numEdgesGlobal = 0;
  std::vector<double> loadedEdgeX;  // per point of the loaded mesh: an edge's node (3 numbers), where the file has it
  {
    PetscErrorCode ierr = chooseElement(comm, loaded, hdf5, mesh, &loadedNatural, &numEdgesGlobal);
    if (!ierr && quadratic) ierr = placeEdgeNodes(comm, loaded, *mesh, edgeNodes, &loadedEdgeX);
    if (ierr) PetscCall(DMDestroy(&loaded));
    PetscCall(ierr);
  }

  PetscSF migration = nullptr;
  if (size > 1) {
    PetscPartitioner part;
    PetscCall(DMPlexGetPartitioner(loaded, &part));
    if (partitioner == "metis") PetscCall(setMetisPartition(loaded, part));
    else if (partitioner == "rcb") PetscCall(setRcbPartition(loaded, part));
    else PetscCall(PetscPartitionerSetType(part, PETSCPARTITIONERPTSCOTCH));
    DM dist = nullptr;
    const PetscInt overlap = mesh->topoDim == 2 ? 1 : 0;
    PetscCall(DMPlexDistribute(loaded, overlap, &migration, &dist));
    if (deferredFaces) PetscCall(routeDeferredRows(comm, migration, loaded, loadedNatural, &deferredRows));
    if (dist) {
      PetscCall(DMDestroy(&loaded));
      loaded = dist;
    }
  }
  if (deferredFaces) {  // every rank makes the faces and edges of its part (and the point SF's shared ones)
    PetscCall(PetscInfo(nullptr, "aries: %s: faces and edges made by every rank after distribution\n",
                        mesh->filename.c_str()));
    DM interpolated = nullptr;
    PetscCall(loading::interpolateMesh(loaded, &interpolated, &mesh->cellCorners));
    PetscCall(DMDestroy(&loaded));
    loaded = interpolated;
  }
  mesh->dm = loaded;
  PetscCall(PetscObjectSetName((PetscObject)mesh->dm, "aries_mesh"));
  PetscCall(DMPlexGetHeightStratum(mesh->dm, 0, &mesh->cStart, &mesh->cEnd));
  PetscCall(DMPlexGetDepthStratum(mesh->dm, 0, &mesh->vStart, &mesh->vEnd));

  std::vector<PetscInt> pointNatural;
  std::vector<double> pointEdgeX;
  PetscCall(migrateEdgeNodes(migration, loadedEdgeX, mesh->dm, &pointEdgeX));
  PetscCall(numberNaturally(migration, loadedNatural, mesh, &pointNatural));  // destroys the migration SF
  if (deferredFaces) PetscCall(labelDeferredRows(comm, mesh, deferredRows));
  if (mesh->quadratic) PetscCall(refineToQuadratic(mesh, pointNatural, numEdgesGlobal, pointEdgeX));

  // PETSc's mesh viewer (-dm_view[ :file:format], e.g. -dm_view ::ascii_info_detail or -dm_view hdf5:mesh.h5) on the
  // distributed mesh.
  PetscCall(DMViewFromOptions(mesh->dm, nullptr, "-dm_view"));

  PetscCall(restBoundingBox(comm, mesh));
  PetscFunctionReturn(0);
}

namespace {
const char *const kSetLabels[] = {"Face Sets", "Edge Sets", "Vertex Sets", "Cell Sets"};

const char *labelForDimension(const Mesh &mesh, PetscInt dim) {
  if (dim == 0) return "Vertex Sets";
  if (dim == mesh.topoDim) return "Cell Sets";
  if (dim == mesh.topoDim - 1) return "Face Sets";
  return "Edge Sets";
}
}  // namespace

namespace {

// The points of a gmsh physical group on this rank (the strata that mark it), and whether any rank has one.
PetscErrorCode physicalGroupPoints(const Mesh &mesh, const std::string &idOrName, std::vector<PetscInt> *points,
                                   bool *found) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  // (label, value): the "... Sets" label of the group's dimension, or, with -dm_plex_gmsh_use_regions, the label
  // PETSc names after the group.
  std::vector<std::pair<std::string, PetscInt>> lookups;
  PetscInt tag;
  if (core::parseInteger(idOrName, &tag)) {
    for (const char *l : {"Face Sets", "Edge Sets", "Vertex Sets"}) lookups.emplace_back(l, tag);
    for (const auto &kv : mesh.physicalNames)
      if (kv.second.tag == tag && kv.second.dim < mesh.topoDim) lookups.emplace_back(kv.first, tag);
  } else {
    auto it = mesh.physicalNames.find(idOrName);
    if (it != mesh.physicalNames.end()) {
      lookups.emplace_back(labelForDimension(mesh, it->second.dim), it->second.tag);
      lookups.emplace_back(it->first, it->second.tag);
    }
  }
  std::set<PetscInt> pts;
  for (const auto &[labelName, tag] : lookups) {
    DMLabel label;
    PetscCall(DMGetLabel(mesh.dm, labelName.c_str(), &label));
    if (!label) continue;
    IS is;
    PetscCall(DMLabelGetStratumIS(label, tag, &is));
    if (!is) continue;
    PetscInt np;
    const PetscInt *p;
    PetscCall(ISGetLocalSize(is, &np));
    PetscCall(ISGetIndices(is, &p));
    pts.insert(p, p + np);
    PetscCall(ISRestoreIndices(is, &p));
    PetscCall(ISDestroy(&is));
  }
  int localFound = !pts.empty(), anyFound = 0;
  PetscCallMPI(MPI_Allreduce(&localFound, &anyFound, 1, MPI_INT, MPI_MAX, comm));
  *found = anyFound != 0;
  points->assign(pts.begin(), pts.end());
  PetscFunctionReturn(0);
}

}  // namespace

PetscErrorCode physicalGroupVertices(const Mesh &mesh, const std::string &idOrName, std::vector<PetscInt> *vertices,
                                     bool *found) {
  std::vector<PetscInt> points;
  PetscFunctionBeginUser;
  PetscCall(physicalGroupPoints(mesh, idOrName, &points, found));
  std::set<PetscInt> verts;
  for (PetscInt point : points) {
    PetscInt nc, *closure = nullptr;
    PetscCall(DMPlexGetTransitiveClosure(mesh.dm, point, PETSC_TRUE, &nc, &closure));
    for (PetscInt k = 0; k < nc; ++k) {
      const PetscInt q = closure[2 * k];
      if (q >= mesh.vStart && q < mesh.vEnd) verts.insert(q);
    }
    PetscCall(DMPlexRestoreTransitiveClosure(mesh.dm, point, PETSC_TRUE, &nc, &closure));
  }
  vertices->assign(verts.begin(), verts.end());
  PetscFunctionReturn(0);
}

PetscErrorCode physicalGroupFacets(const Mesh &mesh, const std::string &idOrName, std::vector<PetscInt> *facets,
                                   bool *found) {
  std::vector<PetscInt> points;
  PetscInt fStart, fEnd;
  PetscFunctionBeginUser;
  PetscCall(physicalGroupPoints(mesh, idOrName, &points, found));
  PetscCall(DMPlexGetHeightStratum(mesh.dm, 1, &fStart, &fEnd));
  facets->clear();
  for (PetscInt point : points)
    if (point >= fStart && point < fEnd) facets->push_back(point);
  PetscFunctionReturn(0);
}

PetscErrorCode ownedGroupFacets(const Mesh &mesh, const std::vector<char> &copy, const std::string &idOrName,
                                const std::string &option, const char *purpose, std::vector<PetscInt> *owned) {
  std::vector<PetscInt> facets;
  PetscInt pStart, pEnd;
  bool found = false;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(mesh.dm, &pStart, &pEnd));
  PetscCall(physicalGroupFacets(mesh, idOrName, &facets, &found));
  owned->clear();
  for (PetscInt f : facets)
    if (!copy[f - pStart]) owned->push_back(f);
  PetscInt count = static_cast<PetscInt>(owned->size()), total = 0;
  PetscCallMPI(MPI_Allreduce(&count, &total, 1, MPIU_INT, MPI_SUM, PetscObjectComm((PetscObject)mesh.dm)));
  if (found && total > 0) PetscFunctionReturn(0);
  std::string known;
  PetscCall(describePhysicalGroups(mesh, &known));
  SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option %s: %s in mesh '%s' (%s; physical groups present: %s)",
          option.c_str(), found ? "the group has no boundary facets" : "no such physical group", mesh.filename.c_str(),
          purpose, known.c_str());
}

PetscErrorCode regionLabel(const Mesh &mesh, const std::string &idOrName, DMLabel *label, PetscInt *value) {
  PetscFunctionBeginUser;
  *label = nullptr;
  std::string name;
  if (core::parseInteger(idOrName, value)) {
    for (const auto &kv : mesh.physicalNames)
      if (kv.second.tag == *value && kv.second.dim == mesh.topoDim) name = kv.first;
  } else {
    auto it = mesh.physicalNames.find(idOrName);
    if (it == mesh.physicalNames.end() || it->second.dim != mesh.topoDim)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -regions: '%s' is not a volume physical group of '%s'",
              idOrName.c_str(), mesh.filename.c_str());
    name = it->first;
    *value = it->second.tag;
  }
  PetscCall(DMGetLabel(mesh.dm, "Cell Sets", label));
  if (!*label && !name.empty()) PetscCall(DMGetLabel(mesh.dm, name.c_str(), label));
  if (!*label)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -regions: mesh '%s' has no cell region '%s'",
            mesh.filename.c_str(), idOrName.c_str());
  PetscFunctionReturn(0);
}

PetscErrorCode describePhysicalGroups(const Mesh &mesh, std::string *text) {
  MPI_Comm comm;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  std::ostringstream out;
  for (const char *labelName : kSetLabels) {
    DMLabel label;
    PetscCall(DMGetLabel(mesh.dm, labelName, &label));
    std::set<PetscInt> values;
    if (label) {
      IS vis;
      PetscCall(DMLabelGetValueIS(label, &vis));
      PetscInt nv;
      const PetscInt *vals;
      PetscCall(ISGetLocalSize(vis, &nv));
      PetscCall(ISGetIndices(vis, &vals));
      values.insert(vals, vals + nv);
      PetscCall(ISRestoreIndices(vis, &vals));
      PetscCall(ISDestroy(&vis));
    }
    // Union over ranks (sets are small).
    std::vector<int> mine(values.begin(), values.end());
    int n = static_cast<int>(mine.size()), size;
    MPI_Comm_size(comm, &size);
    std::vector<int> counts(size), displs(size);
    PetscCallMPI(MPI_Allgather(&n, 1, MPI_INT, counts.data(), 1, MPI_INT, comm));
    int total = 0;
    for (int p = 0; p < size; ++p) {
      displs[p] = total;
      total += counts[p];
    }
    std::vector<int> all(total);
    PetscCallMPI(MPI_Allgatherv(mine.data(), n, MPI_INT, all.data(), counts.data(), displs.data(), MPI_INT, comm));
    std::set<int> u(all.begin(), all.end());
    if (u.empty()) continue;
    out << labelName << " {";
    bool first = true;
    for (int v : u) {
      out << (first ? "" : ",") << v;
      for (const auto &kv : mesh.physicalNames)
        if (kv.second.tag == v && std::string(labelForDimension(mesh, kv.second.dim)) == labelName)
          out << "=" << kv.first;
      first = false;
    }
    out << "} ";
  }
  *text = out.str().empty() ? "none" : out.str();
  PetscFunctionReturn(0);
}

PetscErrorCode sumOverSharedVertices(const Mesh &mesh, int ncomp, std::vector<double> *values) {
  PetscSF sf;
  PetscInt pStart, pEnd;
  MPI_Datatype unit;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetChart(mesh.dm, &pStart, &pEnd));
  PetscCall(DMGetPointSF(mesh.dm, &sf));
  // The SF is over all points; non-vertex entries stay zero.
  std::vector<double> leaf(static_cast<size_t>(pEnd - pStart) * ncomp, 0.0);
  std::copy(values->begin(), values->end(), leaf.begin() + static_cast<size_t>(mesh.vStart - pStart) * ncomp);
  std::vector<double> root(leaf);
  // One double per vertex goes as MPI_DOUBLE: PETSc 3.18's SF hands a 1-element contiguous type to MPI's own
  // reduction, which rejects MPI_SUM on it (MPI_ERR_OP).
  unit = MPI_DOUBLE;
  if (ncomp > 1) {
    PetscCallMPI(MPI_Type_contiguous(ncomp, MPI_DOUBLE, &unit));
    PetscCallMPI(MPI_Type_commit(&unit));
  }
  PetscCall(PetscSFReduceBegin(sf, unit, leaf.data(), root.data(), MPI_SUM));
  PetscCall(PetscSFReduceEnd(sf, unit, leaf.data(), root.data(), MPI_SUM));
  PetscCall(PetscSFBcastBegin(sf, unit, root.data(), leaf.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(sf, unit, root.data(), leaf.data(), MPI_REPLACE));
  if (ncomp > 1) PetscCallMPI(MPI_Type_free(&unit));
  std::vector<char> isLeaf;
  PetscCall(sharedLeafPoints(mesh.dm, &isLeaf));
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    const std::vector<double> &src = isLeaf[v - pStart] ? leaf : root;
    for (int k = 0; k < ncomp; ++k)
      (*values)[static_cast<size_t>(v - mesh.vStart) * ncomp + k] = src[static_cast<size_t>(v - pStart) * ncomp + k];
  }
  PetscFunctionReturn(0);
}

PetscErrorCode vertexRestPositions(const Mesh &mesh, std::vector<Eigen::Vector3d> *rest) {
  Vec coordsLocal;
  PetscSection coordSection;
  const PetscScalar *coords;
  PetscFunctionBeginUser;
  PetscCall(DMGetCoordinatesLocal(mesh.dm, &coordsLocal));
  PetscCall(DMGetCoordinateSection(mesh.dm, &coordSection));
  PetscCall(VecGetArrayRead(coordsLocal, &coords));
  rest->assign(mesh.vEnd - mesh.vStart, Eigen::Vector3d::Zero());
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
    PetscInt off;
    PetscCall(PetscSectionGetOffset(coordSection, v, &off));
    for (int d = 0; d < mesh.spaceDim; ++d) (*rest)[v - mesh.vStart][d] = coords[off + d];
  }
  PetscCall(VecRestoreArrayRead(coordsLocal, &coords));
  PetscFunctionReturn(0);
}


}  // namespace aries::fem
