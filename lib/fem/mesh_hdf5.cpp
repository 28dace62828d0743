// Parallel mesh input: a gmsh mesh converted once (-mesh_convert) to PETSc's DMPlex HDF5 format, with aries' own root
// attributes (format, physical names, the serial numbering), and read by every rank in parallel (fem/mesh.hpp).
#include "fem/mesh_loading.hpp"

#include "core/errors.hpp"
#include "core/options.hpp"
#include "fem/fem_options.hpp"

#include <hdf5.h>
#include <petscsf.h>
#include <petscviewerhdf5.h>

#include <cstdio>

namespace aries::fem {

namespace loading {

namespace {

constexpr const char *kMeshFormat = "aries-mesh-1";  // the root attribute aries_mesh_format of a converted mesh

// What a converted mesh file says about itself (root attributes written by convertMesh), checked on rank 0.
struct Hdf5MeshFacts {
  long long vertexStart = 0, numCells = 0, numVertices = 0;  // file point numbers: cells [0, numCells), vertices from
                                                              // vertexStart (the serial gmsh mesh's chart)
  long long spaceDim = 3;  // coordinate dimension (PETSc 3.18's loader leaves it at the topological one)
  std::string physicalNames;
};

std::string readHdf5MeshFacts(const std::string &file, Hdf5MeshFacts *facts) {
  std::FILE *probe = std::fopen(file.c_str(), "rb");
  if (!probe) return "cannot open mesh '" + file + "' (-dm_plex_filename)";
  std::fclose(probe);
  H5E_auto2_t func;
  void *data;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // our message, not HDF5's stack
  std::string err;
  hid_t f = H5Fis_hdf5(file.c_str()) > 0 ? H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT) : -1;
  const auto readString = [&](const char *name, std::string *value) {
    if (H5Aexists(f, name) <= 0) return false;
    hid_t a = H5Aopen(f, name, H5P_DEFAULT), t = H5Aget_type(a);
    std::string buf(H5Tget_size(t), '\0');
    const bool ok = H5Aread(a, t, buf.data()) >= 0;
    H5Tclose(t);
    H5Aclose(a);
    *value = buf.c_str();
    return ok;
  };
  const auto readInt = [&](const char *name, long long *value) {
    if (H5Aexists(f, name) <= 0) return false;
    hid_t a = H5Aopen(f, name, H5P_DEFAULT);
    const bool ok = H5Aread(a, H5T_NATIVE_LLONG, value) >= 0;
    H5Aclose(a);
    return ok;
  };
  std::string format;
  if (f < 0) {
    err = "mesh '" + file + "' (-dm_plex_filename) is not an HDF5 file";
  } else if (!readString("aries_mesh_format", &format) || format != kMeshFormat) {
    err = "mesh '" + file + "' (-dm_plex_filename) is an HDF5 file but not a mesh converted by aries (make one with "
          "aries -dm_plex_filename MESH.msh -mesh_convert '" + file + "')";
  } else if (!readInt("aries_vertex_start", &facts->vertexStart) || !readInt("aries_num_cells", &facts->numCells) ||
             !readInt("aries_num_vertices", &facts->numVertices) || !readInt("aries_space_dim", &facts->spaceDim) ||
             !readString("aries_physical_names", &facts->physicalNames)) {
    err = "mesh '" + file + "' (-dm_plex_filename) is incomplete: an aries_* attribute is missing; convert it again";
  }
  if (f >= 0) H5Fclose(f);
  H5Eset_auto2(H5E_DEFAULT, func, data);
  return err;
}

}  // namespace

// A converted mesh, read by every rank in parallel (PETSc's DMPlex HDF5 format: each rank loads a contiguous share of
// the points with their cones, coordinates and labels), and the natural id of every loaded point (from its number in
// the file).
PetscErrorCode readHdf5Mesh(MPI_Comm comm, Mesh *mesh, DM *dm, std::vector<PetscInt> *natural) {
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  Hdf5MeshFacts facts;
  std::string err;
  if (rank == 0) err = readHdf5MeshFacts(mesh->filename, &facts);
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  long long numbers[4] = {facts.vertexStart, facts.numCells, facts.numVertices, facts.spaceDim};
  PetscCallMPI(MPI_Bcast(numbers, 4, MPI_LONG_LONG, 0, comm));
  mesh->numCellsGlobal = static_cast<PetscInt>(numbers[1]);
  mesh->numVerticesGlobal = static_cast<PetscInt>(numbers[2]);
  PetscCall(parsePhysicalNames(comm, facts.physicalNames, &mesh->physicalNames));

  PetscViewer viewer;
  PetscSF fileToLoaded;
  PetscCall(PetscViewerHDF5Open(comm, mesh->filename.c_str(), FILE_MODE_READ, &viewer));
  PetscCall(PetscViewerPushFormat(viewer, PETSC_VIEWER_HDF5_PETSC));
  PetscCall(DMCreate(comm, dm));
  PetscCall(DMSetType(*dm, DMPLEX));
  PetscCall(PetscObjectSetName((PetscObject)*dm, "aries_mesh"));
  PetscCall(DMPlexTopologyLoad(*dm, viewer, &fileToLoaded));
  PetscCall(DMPlexLabelsLoad(*dm, viewer, fileToLoaded));
  PetscCall(DMSetCoordinateDim(*dm, static_cast<PetscInt>(numbers[3])));
  PetscCall(DMPlexCoordinatesLoad(*dm, viewer, fileToLoaded));
  PetscCall(PetscViewerPopFormat(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  PetscCall(DMGetDimension(*dm, &mesh->topoDim));
  PetscCall(DMGetCoordinateDim(*dm, &mesh->spaceDim));
  PetscCall(classifyShape(GmshFacts(), mesh));  // a curved surface was checked when it was converted

  // The file numbers its points [0, N), spread over the ranks as the roots of fileToLoaded in rank order.
  PetscInt nroots, pStart, pEnd, rootStart = 0;
  PetscCall(PetscSFGetGraph(fileToLoaded, &nroots, nullptr, nullptr, nullptr));
  PetscCallMPI(MPI_Exscan(&nroots, &rootStart, 1, MPIU_INT, MPI_SUM, comm));
  if (rank == 0) rootStart = 0;
  std::vector<PetscInt> fileNumber(nroots), loaded;
  for (PetscInt i = 0; i < nroots; ++i) fileNumber[i] = rootStart + i;
  PetscCall(DMPlexGetChart(*dm, &pStart, &pEnd));
  loaded.assign(pEnd - pStart, -1);
  PetscCall(PetscSFBcastBegin(fileToLoaded, MPIU_INT, fileNumber.data(), loaded.data(), MPI_REPLACE));
  PetscCall(PetscSFBcastEnd(fileToLoaded, MPIU_INT, fileNumber.data(), loaded.data(), MPI_REPLACE));
  PetscCall(PetscSFDestroy(&fileToLoaded));
  natural->assign(pEnd - pStart, -1);
  const PetscInt vFirst = static_cast<PetscInt>(numbers[0]);
  for (PetscInt p = 0; p < pEnd - pStart; ++p) {
    const PetscInt q = loaded[p];
    if (q >= 0 && q < mesh->numCellsGlobal) (*natural)[p] = q;
    else if (q >= vFirst && q < vFirst + mesh->numVerticesGlobal) (*natural)[p] = q - vFirst;
  }
  PetscFunctionReturn(0);
}

}  // namespace loading

using namespace loading;

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
  PetscCall(readGmshMesh(comm, &mesh, &serial, &natural));
  mesh.dm = serial;
  PetscCall(PetscObjectSetName((PetscObject)serial, "aries_mesh"));
  PetscCall(DMPlexGetHeightStratum(serial, 0, &mesh.cStart, &mesh.cEnd));
  PetscCall(DMPlexGetDepthStratum(serial, 0, &mesh.vStart, &mesh.vEnd));
  PetscCall(checkSimplices(comm, mesh));
  std::string names;
  for (const auto &kv : mesh.physicalNames)
    names += std::to_string(kv.second.dim) + " " + std::to_string(kv.second.tag) + " " + kv.first + "\n";
  PetscInt counts[3] = {mesh.vStart, mesh.numCellsGlobal, mesh.numVerticesGlobal};
  PetscCallMPI(MPI_Bcast(counts, 1, MPIU_INT, 0, comm));  // the vertex stratum's start is known on rank 0
  const std::string tmp = out + ".tmp";
  bool writable = true;
  if (rank == 0) {  // a one-line error here rather than the HDF5 viewer's traceback
    std::FILE *probe = std::fopen(tmp.c_str(), "wb");
    writable = probe != nullptr;
    if (probe) std::fclose(probe);
  }
  PetscCall(core::collectiveCheck(comm, !writable, "cannot write '" + out + "' (-mesh_convert): no such directory or "
                                                   "not writable"));
  PetscViewer viewer;
  PetscCall(PetscViewerHDF5Open(comm, tmp.c_str(), FILE_MODE_WRITE, &viewer));
  PetscCall(PetscViewerPushFormat(viewer, PETSC_VIEWER_HDF5_PETSC));
  PetscCall(DMPlexTopologyView(serial, viewer));
  PetscCall(DMPlexCoordinatesView(serial, viewer));
  PetscCall(DMPlexLabelsView(serial, viewer));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "aries_mesh_format", PETSC_STRING, kMeshFormat));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "aries_source", PETSC_STRING, mesh.filename.c_str()));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "aries_physical_names", PETSC_STRING, names.c_str()));
  const long long numbers[3] = {counts[0], counts[1], counts[2]};
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "aries_vertex_start", PETSC_LONG, &numbers[0]));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "aries_num_cells", PETSC_LONG, &numbers[1]));
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "aries_num_vertices", PETSC_LONG, &numbers[2]));
  const long long spaceDim = mesh.spaceDim;
  PetscCall(PetscViewerHDF5WriteAttribute(viewer, "/", "aries_space_dim", PETSC_LONG, &spaceDim));
  PetscCall(PetscViewerPopFormat(viewer));
  PetscCall(PetscViewerDestroy(&viewer));
  bool renamed = rank != 0 || std::rename(tmp.c_str(), out.c_str()) == 0;
  PetscCall(core::collectiveCheck(comm, !renamed, "cannot write '" + out + "' (-mesh_convert)"));
  PetscCall(PetscPrintf(comm, "aries: wrote '%s' (%lld cells, %lld vertices) from '%s'; run it with -dm_plex_filename %s\n",
                        out.c_str(), numbers[1], numbers[2], mesh.filename.c_str(), out.c_str()));
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
