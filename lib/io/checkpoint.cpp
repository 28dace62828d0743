#include "io/checkpoint.hpp"

#include "core/errors.hpp"
#include "core/options.hpp"
#include "io/io_options.hpp"
#include "io/files.hpp"
#include "io/h5_attributes.hpp"

#include <hdf5.h>

#include <cstdio>

namespace aries::io {

namespace {
constexpr const char *kFormat = "aries-checkpoint-1";

bool writeMatrix(hid_t f, const char *name, const std::vector<double> &v, hsize_t rows) {
  const hsize_t dims[2] = {rows, 3};
  hid_t space = H5Screate_simple(2, dims, nullptr);
  hid_t d = H5Dcreate2(f, name, H5T_NATIVE_DOUBLE, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  const bool ok = d >= 0 && H5Dwrite(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()) >= 0;
  if (d >= 0) H5Dclose(d);
  H5Sclose(space);
  return ok;
}

bool readMatrix(hid_t f, const char *name, hsize_t rows, std::vector<double> *v) {
  if (H5Lexists(f, name, H5P_DEFAULT) <= 0) return false;
  hid_t d = H5Dopen2(f, name, H5P_DEFAULT);
  if (d < 0) return false;
  hid_t space = H5Dget_space(d);
  hsize_t dims[2] = {0, 0};
  const int nd = H5Sget_simple_extent_dims(space, dims, nullptr);
  bool ok = nd == 2 && dims[0] == rows && dims[1] == 3;
  if (ok) {
    v->assign(rows * 3, 0.0);
    ok = H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v->data()) >= 0;
  }
  H5Sclose(space);
  H5Dclose(d);
  return ok;
}
}  // namespace

PetscErrorCode readCheckpointOptions(const std::string &outputBase, CheckpointOptions *o) {
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(core::get(opt::checkpointEvery, &o->every, &set));
  if (o->every > 0) {
    o->path = outputBase.empty() ? std::string("checkpoint.h5") : outputBase + ".checkpoint.h5";
    PetscCall(core::get(opt::checkpoint, &o->path));
  }
  PetscCall(core::get(opt::restart, &o->restart));
  PetscFunctionReturn(0);
}

PetscErrorCode writeCheckpoint(const solver::Simulation &sim, const std::string &path) {
  const fem::Discretization &disc = sim.discretization();
  MPI_Comm comm;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)disc.dm(), &comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  Vec xLocal, vLocal;
  std::vector<double> positions, velocities;
  PetscCall(DMGetLocalVector(disc.dm(), &xLocal));
  PetscCall(DMGetLocalVector(disc.dm(), &vLocal));
  PetscCall(sim.localState(xLocal));
  PetscCall(sim.localVelocity(vLocal));
  PetscCall(disc.diagnostics().gatherVertexField(xLocal, &positions));
  PetscCall(disc.diagnostics().gatherVertexField(vLocal, &velocities));
  PetscCall(DMRestoreLocalVector(disc.dm(), &xLocal));
  PetscCall(DMRestoreLocalVector(disc.dm(), &vLocal));
  std::string err;
  if (rank == 0) {
    const std::string tmp = path + ".tmp";
    const hsize_t nv = positions.size() / 3;
    const long long step = sim.completedSteps(), nvv = static_cast<long long>(nv),
                    nc = static_cast<long long>(disc.mesh().numCellsGlobal);
    const double time = sim.time(), load = disc.load();
    bool ok = makeParentDirectory(path);
    hid_t f = ok ? H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT) : -1;
    ok = f >= 0 && writeMatrix(f, "/positions", positions, nv) && writeMatrix(f, "/velocities", velocities, nv) &&
         writeScalarAttribute(f, "step", H5T_NATIVE_LLONG, step) &&
         writeScalarAttribute(f, "time", H5T_NATIVE_DOUBLE, time) &&
         writeScalarAttribute(f, "load", H5T_NATIVE_DOUBLE, load) &&
         writeScalarAttribute(f, "num_vertices", H5T_NATIVE_LLONG, nvv) &&
         writeScalarAttribute(f, "num_cells", H5T_NATIVE_LLONG, nc);
    ok = ok && writeStringAttribute(f, "format", kFormat) && writeVersionAttributes(f);
    if (f >= 0) ok = H5Fclose(f) >= 0 && ok;
    if (!ok || std::rename(tmp.c_str(), path.c_str()) != 0) err = "cannot write checkpoint '" + path + "'";
  }
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  PetscFunctionReturn(0);
}

PetscErrorCode readCheckpoint(const fem::Mesh &mesh, const std::string &path, CheckpointState *st) {
  MPI_Comm comm;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::string err;
  long long step = 0, nv = 0, nc = 0;
  double scalars[2] = {0, 0};
  if (rank == 0) {
    H5E_auto2_t func;
    void *data;
    H5Eget_auto2(H5E_DEFAULT, &func, &data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // report our own message, not the HDF5 stack
    hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (f < 0) {
      err = "cannot open checkpoint '" + path + "' (-restart): missing or not an HDF5 file";
    } else {
      char fmt[64] = "";
      bool ok = H5Aexists(f, "format") > 0;
      if (ok) {
        hid_t a = H5Aopen(f, "format", H5P_DEFAULT);
        hid_t t = H5Aget_type(a);
        ok = H5Tget_size(t) < sizeof(fmt) && H5Aread(a, t, fmt) >= 0;
        H5Tclose(t);
        H5Aclose(a);
      }
      if (!ok || std::string(fmt) != kFormat) {
        err = "'" + path + "' is not an aries checkpoint (-restart)";
      } else if (!readScalarAttribute(f, "step", H5T_NATIVE_LLONG, &step) ||
                 !readScalarAttribute(f, "time", H5T_NATIVE_DOUBLE, &scalars[0]) ||
                 !readScalarAttribute(f, "load", H5T_NATIVE_DOUBLE, &scalars[1]) ||
                 !readScalarAttribute(f, "num_vertices", H5T_NATIVE_LLONG, &nv) ||
                 !readScalarAttribute(f, "num_cells", H5T_NATIVE_LLONG, &nc)) {
        err = "checkpoint '" + path + "' is incomplete (missing attributes)";
      } else if (nv != mesh.numVerticesGlobal || nc != mesh.numCellsGlobal) {
        err = "checkpoint '" + path + "' was written for a mesh with " + std::to_string(nv) + " vertices and " +
              std::to_string(nc) + " cells, but '" + mesh.filename + "' has " + std::to_string(mesh.numVerticesGlobal) +
              " and " + std::to_string(mesh.numCellsGlobal);
      } else if (!readMatrix(f, "/positions", nv, &st->positions) || !readMatrix(f, "/velocities", nv, &st->velocities)) {
        err = "checkpoint '" + path + "' has missing or malformed /positions or /velocities";
      }
      H5Fclose(f);
    }
    H5Eset_auto2(H5E_DEFAULT, func, data);
  }
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  PetscCallMPI(MPI_Bcast(&step, 1, MPI_LONG_LONG, 0, comm));
  PetscCallMPI(MPI_Bcast(scalars, 2, MPI_DOUBLE, 0, comm));
  const size_t n = 3 * static_cast<size_t>(mesh.numVerticesGlobal);
  st->positions.resize(n);
  st->velocities.resize(n);
  PetscCallMPI(MPI_Bcast(st->positions.data(), static_cast<int>(n), MPI_DOUBLE, 0, comm));
  PetscCallMPI(MPI_Bcast(st->velocities.data(), static_cast<int>(n), MPI_DOUBLE, 0, comm));
  st->step = static_cast<PetscInt>(step);
  st->time = scalars[0];
  st->load = scalars[1];
  PetscFunctionReturn(0);
}

}  // namespace aries::io
