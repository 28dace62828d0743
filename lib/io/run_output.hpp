// What a run writes while it goes: one console line per step, the -stats CSV, the -reactions CSV, the
// -newton_history CSV and the HDF5/XDMF output (-output, -output_every). Implements the solver's StepObserver.
#pragma once

#include "io/checkpoint.hpp"
#include "io/stats.hpp"
#include "io/xdmf_writer.hpp"
#include "solver/simulation.hpp"

#include <cstdio>
#include <string>
#include <vector>

namespace aries::io {

// The fields -output_fields can select (docs/options.md lists them with their meaning), by what computes them.
enum class FieldSource { CellQuantities, StressMeasures, Fibers, Regions, Velocity, Reactions, Markers };
struct OutputField {
  const char *name;
  FieldSource source;
  int components;  // 1 scalar, 3 vector, 9 tensor (row-major 3x3)
  const char *help;
  bool perCell() const { return source < FieldSource::Velocity; }  // else per vertex
};
const std::vector<OutputField> &outputFields();

struct OutputOptions {
  std::string output;      // DIR/NAME
  PetscInt outputEvery = 1;
  std::vector<std::string> fields;  // -output_fields, validated
  std::string stats;       // FILE.csv
  std::string reactions;   // FILE.csv
  std::string newtonHistory;  // FILE.csv: one row per Newton iteration (-newton_history)
};

// `dynamic`: backward Euler (velocities exist).
PetscErrorCode readOutputOptions(bool dynamic, OutputOptions *opts);

class RunOutput final : public solver::StepObserver {
 public:
  ~RunOutput() override;
  // Collective: opens the files. resumeAfterStep >= 0 continues the stats and the XDMF index of a restarted run.
  PetscErrorCode setup(const OutputOptions &opts, const CheckpointOptions &checkpoint,
                       const fem::Discretization &disc, PetscInt resumeAfterStep = -1);
  PetscErrorCode initial(const solver::Simulation &sim) override;
  PetscErrorCode afterStep(const solver::Simulation &sim, const solver::StepReport &report) override;
  double seconds() const { return seconds_; }  // wall time of this rank in initial() and afterStep() so far

 private:
  PetscErrorCode record(const solver::Simulation &sim, const solver::StepReport &report);
  PetscErrorCode writeState(const solver::Simulation &sim, PetscInt step, double time);

  OutputOptions opts_;
  CheckpointOptions checkpoint_;
  MPI_Comm comm_ = MPI_COMM_NULL;
  core::NaturalBlocks vertexBlocks_, cellBlocks_;  // each rank's share of the files' rows (output and checkpoints)
  XdmfWriter writer_;
  StatsWriter stats_;
  std::FILE *reactions_ = nullptr;
  std::FILE *history_ = nullptr;
  PetscLogStage outputStage_ = -1;
  double runStart_ = -1.0;  // wall clock at the start of this run's first step (progress: elapsed time and ETA)
  PetscInt firstStep_ = 0;
  double seconds_ = 0.0;
};

}  // namespace aries::io
