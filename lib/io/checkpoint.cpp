#include "io/checkpoint.hpp"

#include "core/errors.hpp"
#include "core/options.hpp"
#include "io/io_options.hpp"
#include "io/files.hpp"
#include "io/h5_attributes.hpp"
#include "core/h5_blocks.hpp"

#include <hdf5.h>

#include <cstdio>

namespace aries::io {

namespace {
constexpr const char *kFormat = "aries-checkpoint-1";
// The Newton solver's memory (solver::NewtonMemory), one int attribute per field in this order; a checkpoint written
// before a field existed lacks its attribute and restarts with the field's default.
constexpr const char *kMemoryAttributes[] = {"filter_backoff", "filter_skip", "filter_override", "filter_exact_start"};
constexpr int kMemoryFields = sizeof(kMemoryAttributes) / sizeof(kMemoryAttributes[0]);

void memoryToInts(const solver::NewtonMemory &m, int v[kMemoryFields]) {
  v[0] = m.filterBackoff;
  v[1] = m.filterSkip;
  v[2] = m.filterOverride;
  v[3] = m.filterExactStart;
}

// Reads the attributes present into v (absent ones keep their value); false where one cannot be read as an int.
bool readMemoryAttributes(hid_t f, int v[kMemoryFields]) {
  for (int k = 0; k < kMemoryFields; ++k)
    if (H5Aexists(f, kMemoryAttributes[k]) > 0 && !readScalarAttribute(f, kMemoryAttributes[k], H5T_NATIVE_INT, &v[k]))
      return false;
  return true;
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

PetscErrorCode writeCheckpoint(const solver::Simulation &sim, const core::NaturalBlocks &vertices,
                               const std::string &path) {
  const fem::Discretization &disc = sim.discretization();
  MPI_Comm comm;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)disc.dm(), &comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  Vec xLocal, vLocal;
  std::vector<double> owned, positions, velocities, accelerations;
  PetscCall(DMGetLocalVector(disc.dm(), &xLocal));
  PetscCall(DMGetLocalVector(disc.dm(), &vLocal));
  PetscCall(sim.localState(xLocal));
  PetscCall(sim.localVelocity(vLocal));
  PetscCall(disc.diagnostics().ownedVertexValues(xLocal, &owned));
  PetscCall(vertices.toBlocks(owned, 3, &positions));
  PetscCall(disc.diagnostics().ownedVertexValues(vLocal, &owned));
  PetscCall(vertices.toBlocks(owned, 3, &velocities));
  PetscCall(sim.localAcceleration(vLocal));
  PetscCall(disc.diagnostics().ownedVertexValues(vLocal, &owned));
  PetscCall(vertices.toBlocks(owned, 3, &accelerations));
  PetscCall(DMRestoreLocalVector(disc.dm(), &xLocal));
  PetscCall(DMRestoreLocalVector(disc.dm(), &vLocal));
  std::string err;
  int dirOk = rank == 0 ? makeParentDirectory(path) : 1;
  PetscCallMPI(MPI_Bcast(&dirOk, 1, MPI_INT, 0, comm));
  const std::string tmp = path + ".tmp";
  const long long step = sim.completedSteps(), nv = static_cast<long long>(vertices.total()),
                  nc = static_cast<long long>(disc.mesh().numCellsGlobal);
  const double time = sim.time(), load = disc.load();
  int memory[kMemoryFields];
  memoryToInts(sim.newtonMemory(), memory);
  hid_t f = dirOk ? core::createParallelFile(comm, tmp) : -1;
  bool ok = f >= 0 && core::writeBlockDataset(f, "/positions", vertices, positions, 3) &&
            core::writeBlockDataset(f, "/velocities", vertices, velocities, 3) &&
            core::writeBlockDataset(f, "/accelerations", vertices, accelerations, 3) &&
            writeScalarAttribute(f, "acceleration", H5T_NATIVE_INT, sim.hasAcceleration() ? 1 : 0) &&
            writeScalarAttribute(f, "velocity_is_motion", H5T_NATIVE_INT, sim.velocityIsMotion() ? 1 : 0) &&
            writeScalarAttribute(f, "step", H5T_NATIVE_LLONG, step) &&
            writeScalarAttribute(f, "time", H5T_NATIVE_DOUBLE, time) &&
            writeScalarAttribute(f, "load", H5T_NATIVE_DOUBLE, load) &&
            writeScalarAttribute(f, "num_vertices", H5T_NATIVE_LLONG, nv) &&
            writeScalarAttribute(f, "num_cells", H5T_NATIVE_LLONG, nc);
  for (int k = 0; k < kMemoryFields; ++k)
    ok = ok && writeScalarAttribute(f, kMemoryAttributes[k], H5T_NATIVE_INT, memory[k]);
  ok = ok && writeStringAttribute(f, "format", kFormat) && writeVersionAttributes(f);
  if (f >= 0) ok = H5Fclose(f) >= 0 && ok;
  int good = ok, allGood = 0;
  PetscCallMPI(MPI_Allreduce(&good, &allGood, 1, MPI_INT, MPI_MIN, comm));
  if (rank == 0 && (!allGood || std::rename(tmp.c_str(), path.c_str()) != 0)) err = "cannot write checkpoint '" + path + "'";
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  PetscFunctionReturn(0);
}

PetscErrorCode readCheckpoint(const fem::Discretization &disc, const std::string &path, CheckpointState *st) {
  const fem::Mesh &mesh = disc.mesh();
  MPI_Comm comm;
  PetscMPIInt rank;
  PetscFunctionBeginUser;
  PetscCall(PetscObjectGetComm((PetscObject)mesh.dm, &comm));
  PetscCallMPI(MPI_Comm_rank(comm, &rank));
  std::string err;
  long long step = 0, nv = 0, nc = 0;
  int accelFlags[2] = {0, 1};  // attributes acceleration and velocity_is_motion (absent in older checkpoints: 0, 1)
  int &hasAcceleration = accelFlags[0];
  double scalars[2] = {0, 0};
  int memory[kMemoryFields];
  memoryToInts(solver::NewtonMemory{}, memory);  // the defaults, for attributes an older checkpoint lacks
  if (rank == 0) {  // the attributes first: a file that is not a checkpoint of this mesh is one clear error
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
      } else if ((H5Aexists(f, "acceleration") > 0 &&
                  !readScalarAttribute(f, "acceleration", H5T_NATIVE_INT, &accelFlags[0])) ||
                 (H5Aexists(f, "velocity_is_motion") > 0 &&
                  !readScalarAttribute(f, "velocity_is_motion", H5T_NATIVE_INT, &accelFlags[1]))) {
        err = "checkpoint '" + path + "' has a malformed attribute acceleration or velocity_is_motion";
      } else if (!readMemoryAttributes(f, memory)) {
        err = "checkpoint '" + path +
              "' has malformed attributes filter_backoff / filter_skip / filter_override / filter_exact_start";
      } else if (nv != mesh.numVerticesGlobal || nc != mesh.numCellsGlobal) {
        err = "checkpoint '" + path + "' was written for a mesh with " + std::to_string(nv) + " vertices and " +
              std::to_string(nc) + " cells, but '" + mesh.filename + "' has " + std::to_string(mesh.numVerticesGlobal) +
              " and " + std::to_string(mesh.numCellsGlobal);
      }
      H5Fclose(f);
    }
    H5Eset_auto2(H5E_DEFAULT, func, data);
  }
  PetscCall(core::collectiveCheck(comm, !err.empty(), err));
  PetscCallMPI(MPI_Bcast(&step, 1, MPI_LONG_LONG, 0, comm));
  PetscCallMPI(MPI_Bcast(scalars, 2, MPI_DOUBLE, 0, comm));
  PetscCallMPI(MPI_Bcast(memory, kMemoryFields, MPI_INT, 0, comm));
  PetscCallMPI(MPI_Bcast(accelFlags, 2, MPI_INT, 0, comm));
  // Every rank reads its block of rows, then the rows move to the ranks that own those vertices.
  std::vector<PetscInt> natural, local;
  disc.diagnostics().ownedVertexIds(&natural, &local);
  core::NaturalBlocks vertices;
  PetscCall(vertices.setup(comm, mesh.numVerticesGlobal, natural));
  std::vector<double> positions, velocities, accelerations;
  H5E_auto2_t func;
  void *data;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  hid_t f = core::openParallelFile(comm, path);
  bool ok = f >= 0 && core::readBlockDataset(f, "/positions", vertices, 3, &positions) &&
            core::readBlockDataset(f, "/velocities", vertices, 3, &velocities);
  const bool accelOk =
      !ok || !hasAcceleration || core::readBlockDataset(f, "/accelerations", vertices, 3, &accelerations);
  if (f >= 0) H5Fclose(f);
  H5Eset_auto2(H5E_DEFAULT, func, data);
  PetscCall(core::collectiveCheck(comm, !ok, "checkpoint '" + path + "' has missing or malformed /positions or /velocities"));
  PetscCall(core::collectiveCheck(comm, !accelOk,
                                  "checkpoint '" + path + "' has attribute acceleration 1 but a missing or malformed "
                                  "/accelerations"));
  std::vector<double> ownedX, ownedV, ownedA;
  PetscCall(vertices.fromBlocks(positions, 3, &ownedX));
  PetscCall(vertices.fromBlocks(velocities, 3, &ownedV));
  if (hasAcceleration) PetscCall(vertices.fromBlocks(accelerations, 3, &ownedA));
  const size_t numLocal = static_cast<size_t>(mesh.vEnd - mesh.vStart);
  st->positions.assign(3 * numLocal, 0.0);
  st->velocities.assign(3 * numLocal, 0.0);
  st->accelerations.assign(hasAcceleration ? 3 * numLocal : 0, 0.0);
  for (size_t k = 0; k < local.size(); ++k)
    for (int i = 0; i < 3; ++i) {
      st->positions[3 * local[k] + i] = ownedX[3 * k + i];
      st->velocities[3 * local[k] + i] = ownedV[3 * k + i];
      if (hasAcceleration) st->accelerations[3 * local[k] + i] = ownedA[3 * k + i];
    }
  st->step = static_cast<PetscInt>(step);
  st->time = scalars[0];
  st->load = scalars[1];
  st->velocityIsMotion = accelFlags[1] != 0;
  st->newton = solver::NewtonMemory{memory[0], memory[1], memory[2], memory[3]};  // memoryToInts' order
  PetscFunctionReturn(0);
}

}  // namespace aries::io
