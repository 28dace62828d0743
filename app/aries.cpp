// aries: the parallel finite-element solver. Thin: read options, build mesh, discretization and simulation, run.
//   mpirun -n 2 aries -options_file options/bunny_inside_out.yml
// Every option is documented in docs/options.md. Exit codes: 0 success, 1 bad input (one error line on stderr),
// 2 internal error, 3 the simulation failed a step and stopped (-on_failure stop).
#include "fem/discretization.hpp"
#include "fem/fem_options.hpp"
#include "mesh/mesh_options.hpp"
#include "core/errors.hpp"
#include "core/parallel.hpp"
#include "core/options.hpp"
#include "io/io_options.hpp"
#include "io/options_help.hpp"
#include "io/run_output.hpp"
#include "io/version.hpp"
#include "solver/simulation.hpp"

#include <petscsys.h>

#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

using namespace aries;

namespace {

const char kHelp[] =
    "aries: analytic rotation-invariant anisotropic FE solver (PETSc/SNES).\n"
    "  aries -options_file options/SCENE.yml [overrides]      docs/options.md has every option\n";

// Options whose value PETSc reads only at solve or finalize time (viewers, monitors); a strict check at setup
// must not report them as unused.
bool readLater(const std::string &name) {
  return name.find("view") != std::string::npos || name.find("monitor") != std::string::npos ||
         name.find("converged_reason") != std::string::npos || name == "options_left" || name == "strict" ||
         name == "help";
}

// Options of the detached start's own solver (prefix detached_) are read when that phase begins, after setup; a
// multigrid's level and coarse solvers' options (mg_levels_, mg_coarse_) when its hierarchy is first built.
bool readInRun(const std::string &name) {
  return name.rfind("detached_", 0) == 0 || name.find("mg_levels_") != std::string::npos ||
         name.find("mg_coarse_") != std::string::npos;
}

// Options given but not read (so far): a misspelled option would otherwise run silently with its default. After
// setup the options read in the run are not reported yet; at the end `onlyInRun` reports just those (the rest
// were reported after setup).
PetscErrorCode unusedOptions(std::string *unused, bool atEnd, bool onlyInRun) {
  PetscInt n = 0;
  char **names = nullptr, **values = nullptr;
  PetscFunctionBeginUser;
  PetscCall(PetscOptionsLeftGet(nullptr, &n, &names, &values));
  unused->clear();
  for (PetscInt i = 0; i < n; ++i)
    if (!readLater(names[i]) && (atEnd || !readInRun(names[i])) && (!onlyInRun || readInRun(names[i]))) {
      const std::string given = std::string("-") + names[i];
      const std::string near = core::nearestDeclared(given);
      // An option declared by name that this configuration does not read (-predictor_start in a static run) is
      // spelled right: say so rather than suggest it to itself (families such as -bc_clamp_<id>_* get no hint).
      const std::string hint = near.empty()    ? ""
                               : near == given ? " (not read by this configuration)"
                                               : " (did you mean " + near + "?)";
      *unused += std::string(unused->empty() ? "" : ", ") + given + hint;
    }
  PetscCall(PetscOptionsLeftRestore(nullptr, &n, &names, &values));
  PetscFunctionReturn(0);
}

// With -strict an unused option is an error; otherwise one warning line on stderr names them all. Checked after
// setup and at the end of the run.
PetscErrorCode checkUnusedOptions(MPI_Comm comm, PetscBool strict, bool atEnd) {
  std::string unused;
  PetscFunctionBeginUser;
  PetscCall(unusedOptions(&unused, atEnd, atEnd && !strict));
  if (unused.empty()) PetscFunctionReturn(0);
  if (strict)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "-strict: unknown or unused option(s) %s (misspelled, or not used by this configuration; see "
            "docs/options.md)",
            unused.c_str());
  PetscCall(PetscFPrintf(comm, PETSC_STDERR,
                         "aries: warning: unknown or unused option(s) %s (misspelled, or not used by this "
                         "configuration; see docs/options.md; -strict makes this an error)\n",
                         unused.c_str()));
  PetscFunctionReturn(0);
}

// The run's resources, one line: wall times (the largest over the ranks) of the setup (options, mesh, layout, files),
// the steps (of which the model's evaluations: energy, gradient, Hessian) and the output (statistics and files), and
// every rank's peak resident memory (getrusage; min / median / max beyond 8 ranks). Collective.
PetscErrorCode printResources(MPI_Comm comm, double setupSeconds, const solver::RunSummary &summary,
                              double outputSeconds) {
  PetscFunctionBeginUser;
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  std::vector<double> rss;  // MB, rank 0 only
  PetscCall(core::gatherOnRoot(comm, {usage.ru_maxrss / 1024.0}, &rss));
  double mine[3] = {setupSeconds, summary.assemblySeconds, outputSeconds}, most[3];
  PetscCallMPI(MPI_Reduce(mine, most, 3, MPI_DOUBLE, MPI_MAX, 0, comm));
  std::string mem;
  if (rss.size() <= 8) {
    for (size_t r = 0; r < rss.size(); ++r) mem += (r ? " / " : "") + std::to_string((long)(rss[r] + 0.5));
  } else {
    std::vector<double> sorted(rss);
    std::sort(sorted.begin(), sorted.end());
    mem = "min " + std::to_string((long)(sorted.front() + 0.5)) + ", median " +
          std::to_string((long)(sorted[sorted.size() / 2] + 0.5)) + ", max " +
          std::to_string((long)(sorted.back() + 0.5)) + ", rank 0 " + std::to_string((long)(rss[0] + 0.5));
  }
  PetscCall(PetscPrintf(comm,
                        "aries: wall time setup %.3f s, steps %.3f s (model evaluations %.3f s), output %.3f s; peak "
                        "memory per rank %s MB\n",
                        most[0], summary.totalSeconds, most[1], most[2], mem.c_str()));
  PetscFunctionReturn(0);
}

PetscErrorCode run(int *exitCode) {
  MPI_Comm comm = PETSC_COMM_WORLD;
  PetscLogStage setupStage;
  PetscBool strict = PETSC_FALSE, help = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscBool showVersion = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-help", &help));
  io::registerOptionSections();
  PetscCall(core::get(io::opt::version, &showVersion));
  PetscBool haveMesh = PETSC_FALSE;
  PetscCall(PetscOptionsHasName(nullptr, nullptr, "-dm_plex_filename", &haveMesh));
  if (help || showVersion) {  // PETSc has printed its own help / version text by now
    // (kHelp, the usage, is at the top of PETSc's help text: PetscInitialize prints it)
    PetscCall(PetscPrintf(comm, "aries %s (git %s)\n", io::version(), io::gitCommit()));
    if (help) PetscCall(io::printOptionsHelp(comm));
    if (help && !haveMesh)
      PetscCall(PetscPrintf(comm, "The SNES, KSP, PC and DM options of a run are listed by PETSc when -help is given "
                                  "with a mesh, e.g. aries -options_file options/bunny_inside_out.yml -help\n"));
    // With a mesh, -help sets the run up (PETSc lists each object's options as it is configured) and stops there.
    if (!(help && haveMesh)) PetscFunctionReturn(0);
  }
  PetscCall(core::get(io::opt::strict, &strict));
  std::string convertTo;
  PetscBool convert = PETSC_FALSE;
  PetscCall(core::get(fem::opt::meshConvert, &convertTo, &convert));
  if (convert) {  // a one-time conversion, not a run
    PetscCall(fem::convertMesh(comm, convertTo));
    PetscCall(checkUnusedOptions(comm, strict, false));
    PetscFunctionReturn(0);
  }
  const double setupStart = MPI_Wtime();
  PetscCall(PetscLogStageRegister("setup", &setupStage));
  PetscCall(PetscLogStagePush(setupStage));
  solver::SimulationOptions simOpts;
  PetscCall(solver::readSimulationOptions(&simOpts));
  io::OutputOptions outOpts;
  PetscCall(io::readOutputOptions(simOpts.integrator == solver::Integrator::BackwardEuler, &outOpts));
  io::CheckpointOptions ckOpts;
  PetscCall(io::readCheckpointOptions(outOpts.output, &ckOpts));
  fem::Mesh mesh;
  PetscCall(fem::loadMesh(comm, &mesh));
  fem::FemOptions femOpts;
  PetscCall(fem::readFemOptions(mesh, solver::syntheticStart(simOpts.initial), &femOpts));
  std::unique_ptr<fem::Discretization> disc;
  PetscCall(fem::Discretization::create(
      mesh, femOpts, simOpts.integrator == solver::Integrator::BackwardEuler ? simOpts.dt : 0.0, &disc));
  solver::Simulation sim;
  PetscCall(sim.setup(*disc, simOpts));
  PetscInt resumeStep = -1;
  if (!ckOpts.restart.empty()) {
    io::CheckpointState st;
    PetscCall(io::readCheckpoint(*disc, ckOpts.restart, &st));
    if (st.step > simOpts.steps)
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "checkpoint '%s' is at step %d, beyond -steps %d",
              ckOpts.restart.c_str(), (int)st.step, (int)simOpts.steps);
    PetscCall(sim.resume(st.positions, st.velocities, st.accelerations, st.velocityIsMotion, st.step, st.time, st.load,
                         st.newton));
    resumeStep = st.step;
    PetscCall(PetscPrintf(comm, "aries: restarting from '%s' after step %d (t = %g)%s\n", ckOpts.restart.c_str(),
                          (int)st.step, st.time, st.step == simOpts.steps ? ": already at the last step, nothing to do" : ""));
  }
  if (help) {  // everything is configured and PETSc has listed its options: nothing is computed or written
    PetscCall(PetscLogStagePop());
    PetscFunctionReturn(0);
  }
  // Every option is read by now except the output's own, which were read first: check before any file is written.
  PetscCall(checkUnusedOptions(comm, strict, false));
  io::RunOutput output;
  PetscCall(output.setup(outOpts, ckOpts, *disc, resumeStep));
  PetscCall(PetscLogStagePop());
  const double setupSeconds = MPI_Wtime() - setupStart;

  PetscMPIInt size;
  PetscCallMPI(MPI_Comm_size(comm, &size));
  const auto &m = disc->material(0);
  PetscCall(PetscPrintf(comm, "aries %s (git %s)\n", io::version(), io::gitCommit()));
  PetscCall(PetscPrintf(comm, "aries: %s, %d cells, %d vertices (%d Dirichlet), %d ranks; energy %s (singularity %s); "
                              "%s, %d steps, dt %g; L = %.6g\n",
                        mesh.filename.c_str(), (int)mesh.numCellsGlobal, (int)mesh.numVerticesGlobal,
                        (int)disc->numBoundaryVerticesGlobal(), (int)size, energies::energyName(m.kind),
                        energies::singularityName(m.singularity.mode),
                        simOpts.integrator == solver::Integrator::Static ? "static" : "backward Euler",
                        (int)simOpts.steps, simOpts.dt, mesh.diagonal));
  if (const energies::Material *band = disc->scaleFreeBandMaterial())  // not the paper's band: say so
    PetscCall(PetscPrintf(comm, "aries: energy %s: the singularity mollifier's band is on the scale-free coordinate, "
                                "eps %g (-mollifier_measure, -mollifier_eps; docs/options.md, The scale-free band)\n",
                          energies::energyName(band->kind), band->singularity.mollifier.eps));
  solver::RunSummary summary;
  PetscCall(sim.run(&output, &summary));
  const std::string stepsRun = summary.firstStep > 1  // after -restart the averages cover the steps this run made
                                   ? "steps " + std::to_string(summary.firstStep) + "-" + std::to_string(summary.stepsDone)
                                   : std::to_string(summary.stepsDone) + " steps";
  PetscCall(PetscPrintf(comm,
                        "aries: %s, %d DoFs: Newton %.2f/step, PCG %.1f/step, %.4f s/step (total %.2f s); "
                        "safeguard halvings %d, load sub-steps %d%s\n",
                        stepsRun.c_str(), (int)summary.dofs, summary.avgNewton, summary.avgLinear,
                        summary.avgSeconds, summary.totalSeconds, (int)summary.safeguardHalvings,
                        (int)summary.loadSubsteps,
                        summary.failedSteps ? (", FAILED steps " + std::to_string(summary.failedSteps)).c_str() : ""));
  if (summary.nested)
    PetscCall(PetscPrintf(comm, "aries: coarse levels (not in the counts above; in the times): Newton %.2f/step, PCG "
                                "%.1f/step\n",
                          summary.coarseNewton, summary.coarseLinear));
  PetscCall(printResources(comm, setupSeconds, summary, output.seconds()));
  if (!outOpts.output.empty()) PetscCall(PetscPrintf(comm, "aries: output %s.xmf\n", outOpts.output.c_str()));
  if (summary.failed) {
    PetscCall(PetscPrintf(comm, "aries: step %d failed (%s); stopped (-on_failure stop). The last accepted state was "
                                "written.\n",
                          (int)summary.stepsDone, summary.lastReason.c_str()));
    *exitCode = 3;
  }
  PetscCall(checkUnusedOptions(comm, strict, true));
  PetscFunctionReturn(0);
}

// PETSc opens -options_file / -options_file_yaml inside PetscInitialize and reports a missing one as a page of PETSc
// error text: check them first, so a mistyped scene path is one line. Empty string = all readable.
std::string optionsFileProblem(int argc, char **argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string opt = argv[i];
    if (opt != "-options_file" && opt != "-options_file_yaml") continue;
    if (i + 1 >= argc) return "option " + opt + " needs a file name";
    const std::string file = argv[++i];
    struct stat st;
    if (stat(file.c_str(), &st) != 0 || !std::ifstream(file))
      return "options file '" + file + "' (" + opt + ") does not exist or is not readable";
    if (!S_ISREG(st.st_mode)) return "options file '" + file + "' (" + opt + ") is not a regular file";
  }
  return {};
}

}  // namespace

int main(int argc, char **argv) {
  // MPI first (PETSc then leaves finalizing it to us), so only rank 0 reports a bad options file.
  MPI_Init(&argc, &argv);
  const std::string problem = optionsFileProblem(argc, argv);
  if (!problem.empty()) {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) std::fprintf(stderr, "aries: error: %s\n", problem.c_str());
    MPI_Finalize();
    return 1;
  }
  PetscErrorCode ierr = PetscInitialize(&argc, &argv, nullptr, kHelp);
  if (ierr) return 2;
  int exitCode = 0;
  ierr = core::installErrorHandler("aries");
  if (!ierr) ierr = run(&exitCode);
  if (ierr) {
    exitCode = core::exitCodeFor(ierr);
    PetscOptionsClear(nullptr);  // the error is the message; keep PetscFinalize quiet
    PetscMPIInt size = 1;
    MPI_Comm_size(PETSC_COMM_WORLD, &size);
    if (exitCode == 2 && size > 1) MPI_Abort(PETSC_COMM_WORLD, exitCode);  // ranks may be stuck in a collective
  }
  PetscFinalize();
  MPI_Finalize();
  return exitCode;
}
