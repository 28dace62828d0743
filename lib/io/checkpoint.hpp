// Checkpoint / restart (-checkpoint_every K, -checkpoint FILE, -restart FILE).
// A checkpoint is one HDF5 file (written and read in parallel, core/h5_blocks.hpp) with the state in natural (gmsh) vertex
// order: /positions, /velocities and /accelerations (the last step's, for -predictor_acceleration; zero where attribute
// acceleration is 0: none to extrapolate; a checkpoint without them restarts with none; attribute velocity_is_motion:
// 0 where the velocities are a recovery from a synthetic start or an unconverged step's, solver::Simulation)
// (vertices x 3), and the attributes step, time, load (parameter of the prescribed motion), filter_backoff,
// filter_skip, filter_override and filter_exact_start (the Newton solver's memory, solver::NewtonMemory; a checkpoint
// without them restarts with none),
// num_vertices, num_cells, format. It is written under a temporary name and renamed when complete, so a run killed at any moment leaves the
// previous checkpoint intact. Natural ordering makes a checkpoint restartable on any number of ranks.
#pragma once

#include "solver/simulation.hpp"

#include <string>
#include <vector>

namespace aries::io {

struct CheckpointOptions {
  std::string path;      // where checkpoints go (default DIR/NAME.checkpoint.h5 with -output, else checkpoint.h5)
  PetscInt every = 0;    // 0: no checkpoints
  std::string restart;   // checkpoint to continue from
};

PetscErrorCode readCheckpointOptions(const std::string &outputBase, CheckpointOptions *opts);

struct CheckpointState {
  std::vector<double> positions, velocities;  // per local vertex (v - vStart), x3; filled on the owned vertices
  std::vector<double> accelerations;          // likewise; empty: none to extrapolate
  bool velocityIsMotion = true;               // attribute velocity_is_motion (absent: true)
  PetscInt step = 0;
  double time = 0.0, load = 0.0;
  solver::NewtonMemory newton;  // the Newton solver's memory (attributes filter_*; none if absent)
};

// Collective: every rank writes its block of rows (`vertices`: the owned vertices' natural ids) into one file, written
// atomically.
PetscErrorCode writeCheckpoint(const solver::Simulation &sim, const core::NaturalBlocks &vertices,
                               const std::string &path);
// Collective: rank 0 validates the attributes against the mesh, every rank reads a block of rows and receives its
// owned vertices' state.
PetscErrorCode readCheckpoint(const fem::Discretization &disc, const std::string &path, CheckpointState *state);

}  // namespace aries::io
