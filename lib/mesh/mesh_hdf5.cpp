// Parallel mesh input: a gmsh mesh converted once (-mesh_convert) to aries' own HDF5 mesh format, read by every rank in
// parallel (mesh/mesh.hpp). PETSc 3.18's DMPlexTopologyLoad reads the whole topology on rank 0 ("force serial load"),
// so the file holds plain arrays in the natural (gmsh) numbering that each rank reads a block of:
//   /aries/cells      numCells x corners    vertex ids of each cell, in the serial mesh's closure order
//   /aries/vertices   numVertices x spaceDim coordinates
//   /aries/labels/K/cells   n x 2           label K (its name in the root attribute aries_label_names, one per line)
//                                           on cells: the cell's id and the label value
//   /aries/labels/K/points  m x 6           on faces, edges and vertices: one row per (point, cell that contains it):
//                                           the cell's id, the point's dimension, the label value and the point's
//                                           vertex ids (sorted, -1 padded)
// Each rank builds its share of the mesh from its block of cells (DMPlexCreateFromCellListParallelPetsc), and the
// label rows travel to the rank holding their cell, so every copy of a shared face, edge or vertex is labelled. A 3D
// mesh is built as cells and vertices; its faces and edges, and the labels on them, are made after the cells are
// repartitioned (-mesh_faces distributed; mesh_facets.cpp).
#include "mesh/mesh_loading.hpp"

#include "core/errors.hpp"
#include "core/h5_attributes.hpp"
#include "core/h5_blocks.hpp"
#include "core/options.hpp"
#include "mesh/mesh_options.hpp"

#include <hdf5.h>
#include <petscsf.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <sstream>

namespace aries::fem {

namespace loading {

namespace {

constexpr const char *kMeshFormat = "aries-mesh-2";  // root attribute aries_mesh_format (meshes/generate.sh H5_FORMAT)
constexpr int kCellLabelCols = 2;                    // cell, value
using PointLabelRow = std::array<long long, kPointLabelCols>;

// What a converted mesh file says about itself (root attributes written by convertMesh), read on rank 0.
struct Hdf5MeshFacts {
  long long numCells = 0, numVertices = 0, spaceDim = 3, cellDim = 3, corners = 4;
  std::string physicalNames, labelNames;  // "dim tag name" lines; one label name per line
};

std::string readHdf5MeshFacts(const std::string &file, const std::string &option, Hdf5MeshFacts *facts) {
  std::FILE *probe = std::fopen(file.c_str(), "rb");
  if (!probe) return "cannot open mesh '" + file + "' (" + option + ")";
  std::fclose(probe);
  H5E_auto2_t func;
  void *data;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // our message, not HDF5's stack
  std::string err, format;
  hid_t f = H5Fis_hdf5(file.c_str()) > 0 ? H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT) : -1;
  const auto readInt = [&](const char *name, long long *value) {
    return core::readScalarAttribute(f, name, H5T_NATIVE_LLONG, value);
  };
  if (f < 0) {
    err = "mesh '" + file + "' (" + option + ") is not an HDF5 file";
  } else if (!core::readStringAttribute(f, "aries_mesh_format", &format) ||
             format.compare(0, 11, "aries-mesh-") != 0) {
    err = "mesh '" + file + "' (" + option + ") is an HDF5 file but not a mesh converted by aries (make one with "
          "aries -dm_plex_filename MESH.msh -mesh_convert '" + file + "')";
  } else if (format != kMeshFormat) {
    err = "mesh '" + file + "' (" + option + ") was converted by an older aries (format " + format + ", this one "
          "reads " + kMeshFormat + "); convert it again with -mesh_convert";
  } else if (!readInt("aries_num_cells", &facts->numCells) || !readInt("aries_num_vertices", &facts->numVertices) ||
             !readInt("aries_space_dim", &facts->spaceDim) || !readInt("aries_cell_dim", &facts->cellDim) ||
             !readInt("aries_corners", &facts->corners) ||
             !core::readStringAttribute(f, "aries_physical_names", &facts->physicalNames) ||
             !core::readStringAttribute(f, "aries_label_names", &facts->labelNames)) {
    err = "mesh '" + file + "' (" + option + ") is incomplete: an aries_* attribute is missing; convert it again";
  }
  if (f >= 0) H5Fclose(f);
  H5Eset_auto2(H5E_DEFAULT, func, data);
  return err;
}

std::vector<std::string> splitLines(const std::string &text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) lines.push_back(line);
  return lines;
}

// The rows of one label of the serial mesh (rank 0): a row per labelled cell, and a row per labelled lower-dimensional
// point and cell containing it.
PetscErrorCode labelRows(const Mesh &mesh, DMLabel label, const std::vector<PetscInt> &vertexIds,
                         std::vector<double> *cellRows, std::vector<double> *pointRows) {
  IS values;
  PetscInt nv;
  const PetscInt *v;
  PetscFunctionBeginUser;
  PetscCall(DMLabelGetValueIS(label, &values));
  PetscCall(ISGetLocalSize(values, &nv));
  PetscCall(ISGetIndices(values, &v));
  std::vector<long long> ids;
  for (PetscInt k = 0; k < nv; ++k) {
    IS stratum;
    PetscInt np;
    const PetscInt *pts;
    PetscCall(DMLabelGetStratumIS(label, v[k], &stratum));
    if (!stratum) continue;
    PetscCall(ISGetLocalSize(stratum, &np));
    PetscCall(ISGetIndices(stratum, &pts));
    for (PetscInt i = 0; i < np; ++i) {
      PetscInt depth, n, *star = nullptr;
      PetscCall(DMPlexGetPointDepth(mesh.dm, pts[i], &depth));
      if (depth == mesh.topoDim) {
        cellRows->push_back(pts[i] - mesh.cStart);
        cellRows->push_back(v[k]);
        continue;
      }
      PointLabelRow row;
      row.fill(-1);
      row[1] = depth;
      row[2] = v[k];
      PetscCall(closureVertices(mesh.dm, pts[i], mesh.vStart, mesh.vEnd, vertexIds.data(), &ids));
      std::sort(ids.begin(), ids.end());  // a point of a cell is known by its 3 smallest vertex ids (a quadrangle too)
      std::copy(ids.begin(), ids.begin() + std::min<size_t>(ids.size(), 3), row.begin() + 3);
      PetscCall(DMPlexGetTransitiveClosure(mesh.dm, pts[i], PETSC_FALSE, &n, &star));
      for (PetscInt j = 0; j < 2 * n; j += 2) {
        if (star[j] < mesh.cStart || star[j] >= mesh.cEnd) continue;
        row[0] = star[j] - mesh.cStart;
        pointRows->insert(pointRows->end(), row.begin(), row.end());
      }
      PetscCall(DMPlexRestoreTransitiveClosure(mesh.dm, pts[i], PETSC_FALSE, &n, &star));
    }
    PetscCall(ISRestoreIndices(stratum, &pts));
    PetscCall(ISDestroy(&stratum));
  }
  PetscCall(ISRestoreIndices(values, &v));
  PetscCall(ISDestroy(&values));
  PetscFunctionReturn(0);
}

// Collective: rank 0's rows (all of them, `comps` values each, in natural order) written as dataset `name`, every
// rank writing its block.
PetscErrorCode writeRows(MPI_Comm comm, hid_t file, const std::string &name, const std::vector<double> &rows,
                         int comps, bool integer, bool *ok) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  long long total = static_cast<long long>(rows.size() / comps);
  PetscCallMPI(MPI_Bcast(&total, 1, MPI_LONG_LONG, 0, comm));
  std::vector<PetscInt> ids(rank == 0 ? total : 0);
  for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<PetscInt>(i);
  core::NaturalBlocks blocks;
  PetscCall(blocks.setup(comm, static_cast<PetscInt>(total), ids));
  std::vector<double> block;
  PetscCall(blocks.toBlocks(rows, comps, &block));
  if (integer) {
    const std::vector<long long> ints(block.begin(), block.end());  // ids < 2^31: exact in a double
    *ok = core::writeBlockIntDataset(file, name, blocks, ints, comps) && *ok;
  } else {
    *ok = core::writeBlockDataset(file, name, blocks, block, comps) && *ok;
  }
  PetscFunctionReturn(0);
}

// This rank's block of the label rows `name` (`cols` values each, the first a cell id), moved to the ranks that hold
// their cells.
PetscErrorCode receiveLabelRows(MPI_Comm comm, hid_t file, const std::string &name, int cols, PetscInt numCells,
                                std::vector<long long> *mine, bool *ok) {
  PetscMPIInt size;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const long long total = core::datasetRows(file, name);
  core::NaturalBlocks blocks;
  PetscCall(blocks.setupBlocks(comm, static_cast<PetscInt>(std::max(total, 0LL))));
  std::vector<long long> rows;
  *ok = total >= 0 && core::readBlockIntDataset(file, name, blocks, cols, &rows) && *ok;
  std::vector<int> dest(rows.size() / cols);
  for (size_t r = 0; r < dest.size(); ++r) {
    const long long cell = rows[r * cols];
    dest[r] = cell >= 0 && cell < numCells ? core::blockOwner(static_cast<PetscInt>(cell), numCells, size) : 0;
  }
  core::RowRoute route;
  PetscCall(route.setup(comm, dest));
  PetscCall(route.forward(rows, cols, mine));
  PetscFunctionReturn(0);
}

// The natural id of each local vertex of a mesh built by DMPlexCreateFromCellListParallelPetsc: its vertex SF has a
// leaf per local vertex (in the DM's vertex order) whose root is the vertex's row in its owner's block.
PetscErrorCode vertexNaturalIds(MPI_Comm comm, PetscSF vertexSF, PetscInt blockStart, std::vector<PetscInt> *ids) {
  PetscMPIInt size;
  PetscInt nroots, nleaves;
  const PetscInt *local;
  const PetscSFNode *remote;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  std::vector<PetscInt> starts(size);
  PetscCallMPI(MPI_Allgather(&blockStart, 1, MPIU_INT, starts.data(), 1, MPIU_INT, comm));
  PetscCall(PetscSFGetGraph(vertexSF, &nroots, &nleaves, &local, &remote));
  ids->assign(nleaves, -1);
  for (PetscInt k = 0; k < nleaves; ++k) (*ids)[local ? local[k] : k] = starts[remote[k].rank] + remote[k].index;
  PetscFunctionReturn(0);
}

}  // namespace

bool isHdf5Mesh(const std::string &file) { return file.size() > 3 && file.compare(file.size() - 3, 3, ".h5") == 0; }

// Vertices of point p in its closure order, as natural ids (vertexNatural[v - vStart]).
PetscErrorCode closureVertices(DM dm, PetscInt p, PetscInt vStart, PetscInt vEnd, const PetscInt *vertexNatural,
                               std::vector<long long> *ids) {
  PetscInt n, *closure = nullptr;
  PetscFunctionBeginUser;
  ids->clear();
  PetscCall(DMPlexGetTransitiveClosure(dm, p, PETSC_TRUE, &n, &closure));
  for (PetscInt i = 0; i < 2 * n; i += 2)
    if (closure[i] >= vStart && closure[i] < vEnd) ids->push_back(vertexNatural[closure[i] - vStart]);
  PetscCall(DMPlexRestoreTransitiveClosure(dm, p, PETSC_TRUE, &n, &closure));
  PetscFunctionReturn(0);
}

// Labels this rank's copies of the rows' points: each row names a local cell (natural id in this rank's cell block),
// itself (cell rows: cols 2) or the point of its closure with the row's dimension and vertices (cols 6).
PetscErrorCode applyLabelRows(DM dm, DMLabel label, const std::vector<long long> &rows, int cols, PetscInt firstCell,
                              const PetscInt *vertexNatural, bool *ok) {
  PetscInt cStart, cEnd, vStart, vEnd, cellDepth;
  PetscFunctionBeginUser;
  PetscCall(DMPlexGetHeightStratum(dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(dm, 0, &vStart, &vEnd));
  PetscCall(DMPlexGetDepth(dm, &cellDepth));
  std::vector<long long> ids;
  for (size_t r = 0; r < rows.size(); r += cols) {
    const long long cell = rows[r] - firstCell, depth = cols == kCellLabelCols ? cellDepth : rows[r + 1];
    const long long value = cols == kCellLabelCols ? rows[r + 1] : rows[r + 2];
    if (cell < 0 || cell >= cEnd - cStart) {
      *ok = false;
      continue;
    }
    const PetscInt c = cStart + static_cast<PetscInt>(cell);
    PetscInt point = depth == cellDepth ? c : -1;
    if (point < 0) {
      PetscInt n, *closure = nullptr;
      PetscCall(DMPlexGetTransitiveClosure(dm, c, PETSC_TRUE, &n, &closure));
      for (PetscInt i = 0; i < 2 * n && point < 0; i += 2) {
        PetscInt d;
        PetscCall(DMPlexGetPointDepth(dm, closure[i], &d));
        if (d != depth) continue;
        PetscCall(closureVertices(dm, closure[i], vStart, vEnd, vertexNatural, &ids));
        std::sort(ids.begin(), ids.end());
        bool same = true;
        for (size_t j = 0; j < 3 && same; ++j) same = (j < ids.size() ? ids[j] : -1) == rows[r + 3 + j];
        if (same) point = closure[i];
      }
      PetscCall(DMPlexRestoreTransitiveClosure(dm, c, PETSC_TRUE, &n, &closure));
    }
    if (point < 0) *ok = false;
    else PetscCall(DMLabelSetValue(label, point, static_cast<PetscInt>(value)));
  }
  PetscFunctionReturn(0);
}


// A converted mesh, read by every rank in parallel: each rank reads a block of the cells and of the vertices, builds
// its share of the mesh from them, and labels it; the natural id of every point comes from the blocks (cells) and the
// vertex numbers the cells name.
PetscErrorCode readHdf5Mesh(MPI_Comm comm, Mesh *mesh, DM *dm, std::vector<PetscInt> *natural, bool mayDeferFaces,
                            bool *deferred, DeferredLabelRows *deferredRows) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  Hdf5MeshFacts facts;
  std::string err;
  if (rank == 0) err = readHdf5MeshFacts(mesh->filename, mesh->fileOption, &facts);
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  long long numbers[5] = {facts.numCells, facts.numVertices, facts.spaceDim, facts.cellDim, facts.corners};
  PetscCallMPI(MPI_Bcast(numbers, 5, MPI_LONG_LONG, 0, comm));
  const PetscInt numCells = static_cast<PetscInt>(numbers[0]), numVertices = static_cast<PetscInt>(numbers[1]);
  const int spaceDim = static_cast<int>(numbers[2]), cellDim = static_cast<int>(numbers[3]);
  const int corners = static_cast<int>(numbers[4]);
  mesh->numCellsGlobal = numCells;
  mesh->numVerticesGlobal = numVertices;
  PetscCall(parsePhysicalNames(comm, facts.physicalNames, &mesh->physicalNames));
  int namesLength = static_cast<int>(facts.labelNames.size());
  PetscCallMPI(MPI_Bcast(&namesLength, 1, MPI_INT, 0, comm));
  facts.labelNames.resize(namesLength);
  PetscCallMPI(MPI_Bcast(facts.labelNames.data(), namesLength, MPI_CHAR, 0, comm));

  hid_t file = core::openParallelFile(comm, mesh->filename);
  core::NaturalBlocks cellBlocks, vertexBlocks;
  PetscCall(cellBlocks.setupBlocks(comm, numCells));
  PetscCall(vertexBlocks.setupBlocks(comm, numVertices));
  std::vector<long long> cellRows;
  std::vector<double> coords;
  bool ok = file >= 0 && core::readBlockIntDataset(file, "/aries/cells", cellBlocks, corners, &cellRows) &&
            core::readBlockDataset(file, "/aries/vertices", vertexBlocks, spaceDim, &coords);
  PetscCall(core::collectiveCheck(comm, !ok, "mesh '" + mesh->filename + "' (" + mesh->fileOption + "): cannot read its "
                                             "cells and vertices; convert it again"));
  const std::vector<PetscInt> cells(cellRows.begin(), cellRows.end());
  cellRows = std::vector<long long>();
  // A 3D mesh gets its faces and edges after it is distributed (-mesh_faces distributed): made here, on the blocks of
  // the file's order, PETSc 3.18's parallel interpolation spends most of its time on the point SF (14 of 19 s of the
  // 1M-tetrahedron box's setup on 2 ranks), as every block's vertices lie on other ranks.
  *deferred = mayDeferFaces && cellDim == 3;
  deferredRows->names.clear();
  deferredRows->rows.clear();
  // (PETSc 3.18 crashes when asked for the vertex list itself: the natural ids come from the vertex SF instead.)
  PetscSF vertexSF = nullptr;
  PetscCall(DMPlexCreateFromCellListParallelPetsc(comm, cellDim, cellBlocks.blockSize(), vertexBlocks.blockSize(),
                                                  numVertices, corners, *deferred ? PETSC_FALSE : PETSC_TRUE,
                                                  cells.data(), spaceDim,
                                                  coords.data(), &vertexSF, nullptr, dm));
  std::vector<PetscInt> vertexNatural;  // natural id of each local vertex, in the DM's vertex order
  PetscCall(vertexNaturalIds(comm, vertexSF, vertexBlocks.blockStart(), &vertexNatural));
  PetscCall(PetscSFDestroy(&vertexSF));
  PetscCall(PetscObjectSetName((PetscObject)*dm, "aries_mesh"));
  PetscCall(DMGetDimension(*dm, &mesh->topoDim));
  PetscCall(DMGetCoordinateDim(*dm, &mesh->spaceDim));
  PetscCall(classifyShape(GmshFacts(), mesh));  // a curved surface was checked when it was converted
  PetscCall(classifyCells(*dm, mesh));

  const std::vector<std::string> labelNames = splitLines(facts.labelNames);
  for (size_t k = 0; k < labelNames.size(); ++k) {
    DMLabel label;
    PetscCall(DMCreateLabel(*dm, labelNames[k].c_str()));
    PetscCall(DMGetLabel(*dm, labelNames[k].c_str(), &label));
    for (const int cols : {kCellLabelCols, kPointLabelCols}) {
      const std::string name = "/aries/labels/" + std::to_string(k) + (cols == kCellLabelCols ? "/cells" : "/points");
      std::vector<long long> rows;
      PetscCall(receiveLabelRows(comm, file, name, cols, numCells, &rows, &ok));
      if (*deferred && cols == kPointLabelCols) {  // the faces' and edges' rows wait for the faces and edges
        std::vector<long long> now, later;
        for (size_t r = 0; r < rows.size(); r += cols) {
          std::vector<long long> &to = rows[r + 1] == 0 ? now : later;  // column 1: the point's dimension
          to.insert(to.end(), rows.begin() + r, rows.begin() + r + cols);
        }
        rows = std::move(now);
        deferredRows->names.push_back(labelNames[k]);
        deferredRows->rows.push_back(std::move(later));
      }
      PetscCall(applyLabelRows(*dm, label, rows, cols, cellBlocks.blockStart(), vertexNatural.data(), &ok));
    }
  }
  if (file >= 0) H5Fclose(file);
  PetscCall(core::collectiveCheck(comm, !ok, "mesh '" + mesh->filename + "' (" + mesh->fileOption + "): its labels do not "
                                             "match its cells; convert it again"));

  PetscInt pStart, pEnd, cStart, cEnd, vStart, vEnd;
  PetscCall(DMPlexGetChart(*dm, &pStart, &pEnd));
  PetscCall(DMPlexGetHeightStratum(*dm, 0, &cStart, &cEnd));
  PetscCall(DMPlexGetDepthStratum(*dm, 0, &vStart, &vEnd));
  natural->assign(pEnd - pStart, -1);
  for (PetscInt c = cStart; c < cEnd; ++c) (*natural)[c - pStart] = cellBlocks.blockStart() + (c - cStart);
  for (PetscInt v = vStart; v < vEnd; ++v) (*natural)[v - pStart] = vertexNatural[v - vStart];
  PetscFunctionReturn(0);
}

}  // namespace loading

using namespace loading;

// The gmsh mesh read on rank 0 and written as plain natural-order arrays (the format above), each rank writing a block.
PetscErrorCode convertMesh(MPI_Comm comm, const std::string &out) {
  PetscMPIInt rank;
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  Mesh mesh;
  PetscCall(core::get(opt::meshFile, &mesh.filename, &set));
  if (!set || isHdf5Mesh(mesh.filename))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -mesh_convert needs the gmsh mesh to convert: -dm_plex_filename "
                                                   "FILE.msh");
  if (!isHdf5Mesh(out))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -mesh_convert '%s': the converted mesh's name must end in .h5",
            out.c_str());
  DM serial = nullptr;
  std::vector<PetscInt> natural;
  bool deferred = false;  // the converter reads every face on rank 0
  std::vector<long long> noRows;
  PetscCall(readGmshMesh(comm, &mesh, &serial, &natural, false, &deferred, &noRows));
  mesh.dm = serial;
  PetscCall(DMPlexGetHeightStratum(serial, 0, &mesh.cStart, &mesh.cEnd));
  PetscCall(DMPlexGetDepthStratum(serial, 0, &mesh.vStart, &mesh.vEnd));
  const std::string tmp = out + ".tmp";
  bool writable = true;
  if (rank == 0) {  // a one-line error here rather than HDF5's stack
    std::FILE *probe = std::fopen(tmp.c_str(), "wb");
    writable = probe != nullptr;
    if (probe) std::fclose(probe);
  }
  PetscCall(core::collectiveCheck(comm, !writable, "cannot write '" + out + "' (-mesh_convert): no such directory or "
                                                   "not writable"));

  // Rank 0 holds the serial mesh: its cells (closure order), coordinates and labels as rows.
  const int corners = mesh.hexahedra ? 8 : mesh.topoDim + 1;  // one cell type (classifyCells)
  std::vector<PetscInt> vertexIds(mesh.vEnd - mesh.vStart);
  for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) vertexIds[v - mesh.vStart] = v - mesh.vStart;
  std::vector<double> cellRows, coordRows;
  std::vector<long long> ids;
  for (PetscInt c = mesh.cStart; c < mesh.cEnd; ++c) {
    PetscCall(closureVertices(serial, c, mesh.vStart, mesh.vEnd, vertexIds.data(), &ids));
    cellRows.insert(cellRows.end(), ids.begin(), ids.end());
  }
  {
    Vec coordinates;
    PetscSection section;
    const PetscScalar *x;
    PetscCall(DMGetCoordinatesLocal(serial, &coordinates));
    PetscCall(DMGetCoordinateSection(serial, &section));
    PetscCall(VecGetArrayRead(coordinates, &x));
    for (PetscInt v = mesh.vStart; v < mesh.vEnd; ++v) {
      PetscInt off;
      PetscCall(PetscSectionGetOffset(section, v, &off));
      coordRows.insert(coordRows.end(), x + off, x + off + mesh.spaceDim);
    }
    PetscCall(VecRestoreArrayRead(coordinates, &x));
  }
  std::string labelNames;  // every label but PETSc's own (depth, celltype)
  PetscInt numLabels = 0;
  if (rank == 0) PetscCall(DMGetNumLabels(serial, &numLabels));
  for (PetscInt l = 0; l < numLabels; ++l) {
    const char *name;
    PetscCall(DMGetLabelName(serial, l, &name));
    if (std::string(name) != "depth" && std::string(name) != "celltype") labelNames += std::string(name) + "\n";
  }
  int namesLength = static_cast<int>(labelNames.size());
  PetscCallMPI(MPI_Bcast(&namesLength, 1, MPI_INT, 0, comm));
  labelNames.resize(namesLength);
  PetscCallMPI(MPI_Bcast(labelNames.data(), namesLength, MPI_CHAR, 0, comm));

  hid_t file = core::createParallelFile(comm, tmp);
  bool ok = file >= 0;
  PetscCall(writeRows(comm, file, "/aries/cells", cellRows, corners, true, &ok));
  PetscCall(writeRows(comm, file, "/aries/vertices", coordRows, static_cast<int>(mesh.spaceDim), false, &ok));
  const std::vector<std::string> labels = splitLines(labelNames);
  for (size_t k = 0; k < labels.size(); ++k) {
    std::vector<double> onCells, onPoints;
    if (rank == 0) {
      DMLabel label;
      PetscCall(DMGetLabel(serial, labels[k].c_str(), &label));
      PetscCall(labelRows(mesh, label, vertexIds, &onCells, &onPoints));
    }
    const std::string group = "/aries/labels/" + std::to_string(k);
    PetscCall(writeRows(comm, file, group + "/cells", onCells, kCellLabelCols, true, &ok));
    PetscCall(writeRows(comm, file, group + "/points", onPoints, kPointLabelCols, true, &ok));
  }
  std::string names;
  for (const auto &kv : mesh.physicalNames)
    names += std::to_string(kv.second.dim) + " " + std::to_string(kv.second.tag) + " " + kv.first + "\n";
  const long long numbers[5] = {mesh.numCellsGlobal, mesh.numVerticesGlobal, mesh.spaceDim, mesh.topoDim, corners};
  ok = ok && core::writeStringAttribute(file, "aries_mesh_format", kMeshFormat) &&
       core::writeStringAttribute(file, "aries_source", mesh.filename) &&
       core::writeStringAttribute(file, "aries_physical_names", names) &&
       core::writeStringAttribute(file, "aries_label_names", labelNames) &&
       core::writeScalarAttribute(file, "aries_num_cells", H5T_NATIVE_LLONG, numbers[0]) &&
       core::writeScalarAttribute(file, "aries_num_vertices", H5T_NATIVE_LLONG, numbers[1]) &&
       core::writeScalarAttribute(file, "aries_space_dim", H5T_NATIVE_LLONG, numbers[2]) &&
       core::writeScalarAttribute(file, "aries_cell_dim", H5T_NATIVE_LLONG, numbers[3]) &&
       core::writeScalarAttribute(file, "aries_corners", H5T_NATIVE_LLONG, numbers[4]);
  if (file >= 0) ok = H5Fclose(file) >= 0 && ok;
  PetscCall(DMDestroy(&serial));
  bool renamed = ok && (rank != 0 || std::rename(tmp.c_str(), out.c_str()) == 0);
  PetscCall(core::collectiveCheck(comm, !renamed, "cannot write '" + out + "' (-mesh_convert)"));
  PetscCall(PetscPrintf(comm, "aries: wrote '%s' (%lld cells, %lld vertices) from '%s'; run it with -dm_plex_filename %s\n",
                        out.c_str(), numbers[0], numbers[1], mesh.filename.c_str(), out.c_str()));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
