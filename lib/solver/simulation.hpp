// The time loop: quasistatic load stepping (-integrator static) or backward Euler as an incremental potential
// (-integrator beuler), each step a projected-Newton solve (newton.hpp).
//
// Moving boundaries: the prescribed motion is ramped with the load parameter s = min(1, step / -bc_ramp_steps).
// Dirichlet values are eliminated, so moving them displaces the boundary vertices before any line search; the
// alpha safeguard therefore also guards the load increment: if moving the boundary would drop an element's alpha
// below min(-alpha_min, its current alpha), the increment is halved and the step is solved in sub-increments.
//
// Failure policy (-on_failure): stop (default; the run ends with exit code 3 after writing the stats row and the
// last accepted state), halve_dt (retry the step as two half steps, up to -max_step_halvings times), continue (keep
// the last finite iterate, record the reason, go on).
#pragma once

#include "io/stats.hpp"
#include "io/xdmf_writer.hpp"
#include "solver/newton.hpp"

namespace aries::solver {

enum class Integrator { Static, BackwardEuler };
enum class InitialState { Rest, Scramble, Invert };
enum class FailurePolicy { Stop, HalveDt, Continue };

struct SimulationOptions {
  Integrator integrator = Integrator::Static;
  double dt = 1e-2;
  PetscInt steps = 1;
  InitialState initial = InitialState::Rest;
  double scrambleVolumeRatio = 2.0;
  PetscInt scrambleSeed = 1;
  std::string output;
  PetscInt outputEvery = 1;
  std::string stats;
  FailurePolicy onFailure = FailurePolicy::Stop;
  PetscInt maxStepHalvings = 6;
  PetscInt maxLoadHalvings = 20;
};

PetscErrorCode readSimulationOptions(SimulationOptions *opts);

struct RunSummary {
  PetscInt stepsDone = 0, failedSteps = 0;
  double avgNewton = 0.0, avgLinear = 0.0, avgSeconds = 0.0, totalSeconds = 0.0;
  PetscInt dofs = 0, safeguardHalvings = 0, loadSubsteps = 0;
  bool failed = false;  // stopped by a failed step (policy stop)
  std::string lastReason;
};

class Simulation {
 public:
  ~Simulation();
  PetscErrorCode setup(fem::Discretization &disc, const SimulationOptions &opts);
  PetscErrorCode run(RunSummary *summary);
  Vec state() const { return x_; }

 private:
  PetscErrorCode applyInitialState();
  PetscErrorCode advance(double dt, double loadTarget, int depth, NewtonResult *acc, bool *ok, std::string *reason);
  PetscErrorCode solveToLoad(double loadTarget, NewtonResult *acc, bool *ok, std::string *reason);
  PetscErrorCode writeOutput(PetscInt step, double time);
  PetscErrorCode localState(Vec xLocal);

  fem::Discretization *disc_ = nullptr;
  SimulationOptions opts_;
  NewtonSolver newton_;
  Vec x_ = nullptr, v_ = nullptr, xPrev_ = nullptr, vPrev_ = nullptr, xTilde_ = nullptr;
  io::XdmfWriter writer_;
  io::StatsWriter stats_;
  PetscLogStage solveStage_ = -1, outputStage_ = -1;
  PetscInt loadSubsteps_ = 0;
};

// Short name of a SNES outcome for stats and console ("newton_step", "fnorm_rel", "diverged_line_search", ...).
std::string reasonName(const NewtonResult &r);

}  // namespace aries::solver
