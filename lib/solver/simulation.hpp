// The time loop: quasistatic load stepping (-integrator static) or backward Euler as an incremental potential
// (-integrator beuler), each step a projected-Newton solve (newton.hpp).
//
// Moving boundaries: the prescribed motion is ramped with the load parameter s = min(1, step / -bc_ramp_steps).
// Dirichlet values are eliminated from the unknowns; a step's increment of them enters the Newton solve lifted
// (-lift_increments, solver/lifted_increment.cpp): the interior moves with its supports in the first linear solve, and
// the alpha safeguard shortens the combined update (backward Euler under auto: only a step whose supports moved alone
// would fail the safeguard; the others move them alone). Where it cannot (or with -lift_increments never) the
// supports move alone, before any line search, and the safeguard guards that move: if it would drop an element's
// alpha below -alpha_min, the increment is halved and the step is solved in sub-increments.
//
// Failure policy (-on_failure): stop (default; the run ends with exit code 3 after writing the stats row and the
// last accepted state), halve_dt (retry the step as two half steps, up to -max_step_halvings times), continue (keep
// the last finite iterate, record the reason, go on).
#pragma once

#include "solver/newton.hpp"

#include <memory>
#include <string>
#include <vector>

namespace aries::solver {

enum class Integrator { Static, BackwardEuler };
enum class InitialState { Rest, Scramble, Invert, Tutte, CollapsePlane, CollapseLine, CollapsePoint };
enum class FailurePolicy { Stop, HalveDt, Continue };

struct SimulationOptions {
  Integrator integrator = Integrator::Static;
  double dt = 1e-2;
  PetscInt steps = 1;
  InitialState initial = InitialState::Rest;
  double scrambleVolumeRatio = 2.0;
  PetscInt scrambleSeed = 1;
  FailurePolicy onFailure = FailurePolicy::Stop;
  PetscInt maxStepHalvings = 6;
  PetscInt maxLoadHalvings = 20;
  bool predictorStart = false;  // -predictor_start (backward Euler; on by default there)
  bool predictorAcceleration = false;  // -predictor_acceleration (with -predictor_start; on by default there)
  bool detachedStart = false;   // -static_detached_start (static runs from a synthetic start; on by default there)
  bool detachedShapeFirst = true;  // -static_detached_shape_first: the detached relaxation starts without volume terms
  double beulerShapeFirst = 0.0;   // -beuler_shape_first: backward Euler from a start dominated by volume terms, likewise
  EigenFilterMode beulerStartProjection = EigenFilterMode::Abs;  // -beuler_start_psd_projection (read by
                                                                 // Simulation::setup, where the materials are known)
  double beulerShapeFirstTol = 0.0;  // -beuler_shape_first_tol (read where that stage runs): it ends at this many L
  std::vector<std::string> coarseMeshes;  // -coarse_mesh, finest first (nested_start.cpp)
  PetscInt coarseSteps = 1;                // -coarse_steps: the first N steps start from the coarse levels (-1: all)
  NewtonOptions newton;            // the Newton solver's (newton_options.hpp); the detached start's own are read
                                   // when it begins (prefix detached_, starting from these)
};

// A synthetic first state (scramble, invert, collapse): neither rest nor a Tutte map; static or backward Euler, the case
// of the mollifier band's defaults (fem::readFemOptions).
inline bool syntheticStart(InitialState s) { return s != InitialState::Rest && s != InitialState::Tutte; }
// Backward Euler from a synthetic start: the case of -newton_forcing's and the preconditioner's defaults with fiber
// terms (Simulation::setup, the preconditioner rule).
inline bool degenerateDynamicStart(const SimulationOptions &o) {
  return o.integrator == Integrator::BackwardEuler && syntheticStart(o.initial);
}

// The shape stage (shape_first.cpp): where the materials' stretch terms alone fix every cell's shape and some material
// has a volume term, and the volume terms' energy at x exceeds `minRatio` times the other elastic energy (0: always),
// solves from x with the volume terms suspended (x is restored if that solve fails), converged at a Newton step of
// `stageTol` L (0: the solver's own tolerance). Collective.
PetscErrorCode solveShapeFirst(fem::Discretization &disc, NewtonSolver &newton, Vec x, double minRatio,
                               double stageTol, NewtonResult *acc);

// Whether the volume terms' elastic energy at x exceeds `minRatio` times the other elastic energy (false without
// volume terms). Collective; the same answer on every rank (reduced energies).
PetscErrorCode volumeDominated(fem::Discretization &disc, Vec x, double minRatio, bool *dominated);

// Reads every option of the solver layer (the Newton solver's too) into plain data before anything is set up.
PetscErrorCode readSimulationOptions(SimulationOptions *opts);

struct RunSummary {
  PetscInt firstStep = 1, stepsDone = 0, failedSteps = 0;  // steps firstStep..stepsDone ran (> 1 after -restart)
  double avgNewton = 0.0, avgLinear = 0.0, avgSeconds = 0.0, totalSeconds = 0.0;
  bool nested = false;                            // -coarse_mesh: coarse levels solved first in some steps
  double coarseNewton = 0.0, coarseLinear = 0.0;  // their updates and linear iterations per step (all levels)
  double assemblySeconds = 0.0;  // of totalSeconds: the model's evaluations (energy, gradient, Hessian)
  PetscInt dofs = 0, safeguardHalvings = 0, loadSubsteps = 0;
  bool failed = false;  // stopped by a failed step (policy stop)
  std::string lastReason;
};

// What one step did; handed to the observer after the step.
struct StepReport {
  PetscInt step = 0, steps = 0;
  double time = 0.0, wallSeconds = 0.0;
  NewtonResult newton;  // accumulated over load sub-steps and step halvings (this mesh's solves only)
  NewtonResult coarse;  // the coarse levels' solves of the nested start (every level; their history rows name it)
  int coarseStart = -1;  // the nested start: -1 none this step, 0 solved but not taken, 1 taken
  std::string reason;
  bool ok = true;
  bool stopping = false;  // the run ends after this step (last step, or a failure under -on_failure stop)
};

class Simulation;
struct CoarseLevel;  // nested_start.cpp

// Receives the initial state and every step (output, statistics, console). Implemented above the solver layer
// (lib/io), so the time loop does not depend on how results are written.
class StepObserver {
 public:
  virtual ~StepObserver() = default;
  virtual PetscErrorCode initial(const Simulation &sim) = 0;
  virtual PetscErrorCode afterStep(const Simulation &sim, const StepReport &report) = 0;
};

class Simulation {
 public:
  Simulation();
  ~Simulation();
  PetscErrorCode setup(fem::Discretization &disc, const SimulationOptions &opts);
  PetscErrorCode run(StepObserver *observer, RunSummary *summary);
  Vec state() const { return x_; }
  const fem::Discretization &discretization() const { return *disc_; }
  fem::Discretization &discretization() { return *disc_; }
  const SimulationOptions &options() const { return opts_; }
  // Local copy of the state with the Dirichlet values filled (caller restores with DMRestoreLocalVector).
  PetscErrorCode localState(Vec xLocal) const;
  // Velocities (global, free dofs; zero for static runs).
  Vec velocity() const { return v_; }
  // Local copy of the velocities, 0 on the Dirichlet vertices (caller restores with DMRestoreLocalVector).
  PetscErrorCode localVelocity(Vec vLocal) const;
  // The last step's acceleration a_n = (v_n - v_{n-1}) / dt, local copy as localVelocity; hasAcceleration() is false
  // where there is none to extrapolate: before the first step, and where v_n or v_{n-1} is not the body's motion
  // (velocityIsMotion(): false after a scramble, invert or collapse start's first step, which recovers the body, and
  // after a step that did not converge).
  PetscErrorCode localAcceleration(Vec aLocal) const;
  bool hasAcceleration() const { return haveAccel_; }
  bool velocityIsMotion() const { return velocityIsMotion_; }
  PetscInt completedSteps() const { return completedSteps_; }
  double time() const { return time_; }

  // What the Newton solver carries from step to step (checkpointed).
  NewtonMemory newtonMemory() const { return newton_.memory(); }

  // Continue from a saved state (checkpoint): positions, velocities and accelerations of this rank's vertices by local
  // vertex index (v - vStart, 3 values each; only the owned free components are read; accelerations empty: none),
  // whether the velocities are the body's motion, the last completed step, its time, the load parameter and the
  // Newton solver's memory. Collective.
  PetscErrorCode resume(const std::vector<double> &positions, const std::vector<double> &velocities,
                        const std::vector<double> &accelerations, bool velocityIsMotion, PetscInt completedStep,
                        double time, double load, const NewtonMemory &memory);

 private:
  PetscErrorCode applyInitialState();
  // Nested iteration (nested_start.cpp): the coarse levels of -coarse_mesh, set up once; and the start of a step
  // from the coarse levels' solution of the same step, taken when it lowers the total potential within the safeguard.
  PetscErrorCode setupCoarseLevels();
  bool nestedStep(PetscInt step) const;
  PetscErrorCode startFromCoarse(double dt, double loadTarget, bool *used);
  PetscErrorCode restrictTo(CoarseLevel &coarse, Vec xFine, bool positions, Vec xCoarse);
  PetscErrorCode detachedStart(NewtonResult *acc);  // detached_start.cpp
  PetscErrorCode advance(double dt, double loadTarget, int depth, NewtonResult *acc, bool *ok, std::string *reason);
  PetscErrorCode startFromPrediction();
  PetscErrorCode setLoad(double s);
  // The supports alone moved from the current load towards loadTarget: the whole increment, then halves of it (at most
  // `halvings`), until every alpha stays acceptable; *moved: one did (the load is there), else the load is unchanged.
  PetscErrorCode moveSupportsAlone(double loadTarget, PetscInt halvings, bool *moved);
  PetscErrorCode solveToLoad(double loadTarget, NewtonResult *acc, bool *ok, std::string *reason);

  fem::Discretization *disc_ = nullptr;
  SimulationOptions opts_;
  NewtonSolver newton_;
  Vec x_ = nullptr, v_ = nullptr, xPrev_ = nullptr, vPrev_ = nullptr, xTilde_ = nullptr;
  Vec a_ = nullptr, xTry_ = nullptr;  // backward Euler: the last acceleration; the extrapolated start
  bool haveAccel_ = false;            // a_ holds an acceleration to extrapolate
  bool velocityIsMotion_ = true;      // v_ is the body's motion (hasAcceleration's comment)
  PetscLogStage solveStage_ = -1;
  PetscInt completedSteps_ = 0;
  double time_ = 0.0;
  PetscInt loadSubsteps_ = 0;
  int level_ = 0;                         // 0: the mesh of the run; k: the k-th -coarse_mesh
  PetscInt currentStep_ = 0;              // the step being solved
  bool syntheticStart_ = false;           // the state is still the synthetic initial one (scramble, invert, collapse)
  std::unique_ptr<CoarseLevel> coarse_;   // the next coarser level, if any
  NewtonResult coarseWork_;               // the current step's solves on the coarser levels
  int coarseStart_ = -1;                  // and whether their solution started this level's (StepReport)
};


}  // namespace aries::solver
