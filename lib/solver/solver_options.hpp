// The options of the solver layer (time stepping, initial states, Newton), declared once (core/option_decl.hpp).
// Defaults that differ between static and backward-Euler runs are declared per integrator ("static", "beuler").
// docs/options.md explains the Newton strategies in prose after the generated tables.
#pragma once

#include "core/option_decl.hpp"

namespace aries::solver::opt {

using core::choiceOption;
using core::flagOption;
using core::intOption;
using core::OptionDecl;
using core::realOption;

// ---- time stepping and initial state ----
inline constexpr OptionDecl integrator =
    choiceOption("-integrator", "static|beuler",
                 "quasistatic load stepping, or backward Euler (incremental potential, lumped mass)")
        .byDefault("static");
inline constexpr OptionDecl dt =
    realOption("-dt", "X", "time step (beuler; also the time column of static runs)").byDefault("1e-2").above(0);
inline constexpr OptionDecl steps = intOption("-steps", "N", "number of steps").byDefault("1").atLeast(1);
inline constexpr OptionDecl initial =
    choiceOption("-initial", "rest|scramble|invert|tutte|collapse_plane|collapse_line|collapse_point",
                 "the state the first step starts from (see Initial states below); tutte with -uv_map only")
        .byDefault("rest");
inline constexpr OptionDecl scrambleVolumeRatio =
    realOption("-scramble_volume_ratio", "X",
               "scramble: every free vertex uniform in an axis-aligned cube of X times the rest volume (square and "
               "area in 2D) centred at the rest centroid")
        .byDefault("2")
        .above(0);
inline constexpr OptionDecl scrambleSeed =
    intOption("-scramble_seed", "N", "seed of the scramble; the same state for any number of ranks").byDefault("1");
inline constexpr OptionDecl detachedStart =
    flagOption("-static_detached_start",
               "static runs from scramble, invert or collapse starts: step 1 first relaxes the body without its "
               "supports, fits it rigidly onto them, then solves with the supports (see The detached start below)")
        .byDefault("true");
inline constexpr OptionDecl detachedShapeFirst =
    flagOption("-static_detached_shape_first",
               "the detached relaxation first solves without the volume terms, then with the full energy; only where "
               "the stretch terms alone fix every cell's shape (see The detached start below)")
        .byDefault("true");
inline constexpr OptionDecl predictorStart =
    flagOption("-predictor_start",
               "beuler: Newton starts from the prediction x_n + dt v_n when its total potential is lower and the "
               "safeguard accepts it")
        .byDefault("true");
inline constexpr OptionDecl predictorAcceleration =
    flagOption("-predictor_acceleration",
               "beuler, with -predictor_start: the start may also be x_n + dt v_n + dt^2 a_n (a_n the last step's "
               "acceleration), taken where its total potential is lower still and the safeguard accepts it")
        .byDefault("true");
inline constexpr OptionDecl beulerShapeFirst =
    realOption("-beuler_shape_first", "X",
               "beuler from scramble, invert or collapse starts: step 1 first solves without the volume terms where "
               "the start holds over X times as much volume-term as other elastic energy (no fiber terms); 0: never "
               "(see The shape stage below)")
        .byDefault("10")
        .atLeast(0);
inline constexpr OptionDecl beulerShapeFirstTol =
    realOption("-beuler_shape_first_tol", "X",
               "the shape stage of -beuler_shape_first ends once its Newton step is at most X L (L = rest "
               "bounding-box diagonal): it only moves where the full solve starts, and that solve converges to "
               "-newton_tol (see The shape stage below)")
        .byDefault("0.1")
        .above(0)
        .atMost(1);
inline constexpr OptionDecl beulerStartProjection =
    choiceOption("-beuler_start_psd_projection", "clamp|abs",
                 "beuler from scramble, invert or collapse starts with fiber terms, where no shape stage runs: the "
                 "eigenvalue filter of every step, in place of -psd_projection's, where the start holds over "
                 "-beuler_shape_first X times as much volume-term as other elastic energy (see The shape stage below)")
        .byDefault("abs");
inline constexpr OptionDecl onFailure =
    choiceOption("-on_failure", "stop|halve_dt|continue",
                 "a step whose Newton solve fails: stop (exit code 3, last accepted state written), retry as two half "
                 "steps, or keep the last finite iterate and go on")
        .byDefault("stop");
inline constexpr OptionDecl maxStepHalvings =
    intOption("-max_step_halvings", "N", "recursion depth of -on_failure halve_dt").byDefault("6").atLeast(1).atMost(30);

inline constexpr const OptionDecl *kSteppingOptions[] = {
    &integrator, &dt, &steps, &initial, &scrambleVolumeRatio, &scrambleSeed, &detachedStart, &detachedShapeFirst,
    &beulerShapeFirst, &beulerShapeFirstTol, &beulerStartProjection, &predictorStart, &predictorAcceleration, &onFailure,
    &maxStepHalvings};

// ---- nested iteration (solver/nested_start.cpp) ----
using core::wordsOption;
inline constexpr OptionDecl coarseMesh =
    wordsOption("-coarse_mesh", "FILE[,FILE...]",
                "coarse tet meshes of the same body (.msh or .h5), finest first: a step of -coarse_steps is solved on "
                "the coarsest first and each solution, interpolated, starts the next finer solve (see Nested "
                "iteration below)")
        .otherwise("none");
inline constexpr OptionDecl coarseSteps =
    intOption("-coarse_steps", "N",
              "with -coarse_mesh: the first N steps start from the coarse levels' solution (-1: every step); measured "
              "in docs/nested.md")
        .byDefault("-1", "static", "1", "beuler")
        .atLeast(-1);

inline constexpr const OptionDecl *kNestedOptions[] = {&coarseMesh, &coarseSteps};

// ---- Newton ----
inline constexpr OptionDecl newtonTol =
    realOption("-newton_tol", "X",
               "converged when the inf-norm of the Newton step is at most X L dt (beuler) or X L (static), L = rest "
               "bounding-box diagonal (paper Sec. 6); see Convergence below")
        .byDefault("1e-4", "static", "1e-2", "beuler")
        .above(0);
inline constexpr OptionDecl alphaMin =
    realOption("-alpha_min", "X",
               "alpha safeguard (paper Sec. 4.2): no accepted step takes a guarded element's alpha below X; the step "
               "is halved until it holds (see The alpha safeguard below)")
        .byDefault("1e-6")
        .atLeast(0);
inline constexpr OptionDecl psdProjection =
    choiceOption("-psd_projection", "clamp|abs|adaptive|none",
                 "eigenvalue filter of each element's F-space Hessian: clamp negatives to 0, flip them to |lambda| "
                 "(Chen et al. 2024), choose per iteration by the model fit (adaptive), or none (reference)")
        .byDefault("abs", "static", "clamp", "beuler");
inline constexpr OptionDecl psdEigensystem =
    choiceOption("-psd_eigensystem", "analytic|numeric",
                 "analytic: an energy's closed-form eigensystem where it has one (iarap, iarap_lin on tets outside "
                 "the singular band), the numeric eigensolve elsewhere; numeric: the eigensolve everywhere")
        .byDefault("analytic");
inline constexpr OptionDecl psdScope =
    choiceOption("-psd_scope", "point|element",
                 "what the eigenvalue filter projects: each quadrature point's F-space Hessian (9x9 for 3x3 F; the "
                 "closed form where it exists), or each element's whole Hessian in its node coordinates after summing "
                 "its points (numeric: 12x12 for a tet, 24x24 hexahedron, 30x30 P2 tet, 9x9 cloth triangle)")
        .byDefault("point");
inline constexpr OptionDecl psdAdaptiveTol =
    realOption("-psd_adaptive_tol", "X", "adaptive filter: |rho - 1| below X selects clamp, else abs")
        .byDefault("0.01")
        .above(0);
inline constexpr OptionDecl newtonExactHessian =
    flagOption("-newton_exact_hessian",
               "after a full-length update the next Newton system uses the unfiltered Hessian (the true Newton step) "
               "while CG finds it positive definite; at negative curvature that iteration is solved again with the "
               "filter, which the solve then keeps (see Hessian filter below)")
        .byDefault("true");
inline constexpr OptionDecl newtonExactStart =
    flagOption("-newton_exact_start",
               "with -newton_exact_hessian: a solve's first Newton system is unfiltered too where the previous "
               "solve's unfiltered systems were all positive definite (the same fallback to the filter)")
        .byDefault("true");
inline constexpr OptionDecl newtonSubspace =
    intOption("-newton_subspace", "M",
              "subspace step: minimize the exact quadratic model over the Newton direction and the last M updates "
              "of the step (0: plain projected Newton)")
        .byDefault("1")
        .atLeast(0)
        .atMost(7);
inline constexpr OptionDecl newtonSubspaceMax =
    realOption("-newton_subspace_max", "X",
               "0: no limit; X >= 1: the subspace step's coefficient of the Newton direction is at most X, after full "
               "line-search steps only")
        .byDefault("2", "static", "0", "beuler")
        .atLeast(0);
inline constexpr OptionDecl newtonExtrapolate =
    intOption("-newton_extrapolate", "K",
              "where the exact curvature along the Newton direction is negative (the energy is not convex along it), "
              "its full step is doubled up to K times while the energy falls (0: off)")
        .byDefault("0", "static", "6", "beuler")
        .atLeast(0)
        .atMost(10);
inline constexpr OptionDecl newtonLocalSolve =
    intOption("-newton_local_solve", "K",
              "after a Newton update that moved a few vertices far more than the rest (most of its length on at most "
              "5% of the dofs), up to K Newton iterations on those vertices and their neighbours alone, the rest of "
              "the body held, before the next global solve (0: off)")
        .byDefault("0")
        .atLeast(0)
        .atMost(100);
inline constexpr OptionDecl newtonRotation =
    intOption("-newton_rotation", "K",
              "rotational update: the rotational part of each vertex's step follows the circle, up to K doublings of "
              "its angle while the energy falls; -1: off")
        .byDefault("3", "static", "-1", "beuler")
        .atLeast(-1)
        .atMost(6);
// The case of -newton_forcing's default (docs/options.md, "Inexact solves"): backward Euler from a degenerate start
// of a tet solid with fiber terms or a volume term (nu > 0), where solves to -ksp_rtol of directions far from the
// solution ended at -ksp_max_it (3 of 18 fiber scrambles at seed 1; 2 iarap scrambles of the bear at nu 0.45) and
// loose ones cost 0.83-1.03x the time (fiber), 0.42-0.83x (iarap, nu 0.3 and 0.45) and 0.87-1.10x (ortho) with a
// tenth to a third of the CG iterations and none at the limit (bench/results/degenerate_starts_fiber_forcing.md,
// degenerate_starts_volume_forcing.md, degenerate_starts_bear_forcing.md). The paper's degenerate scenes (nu 0, no
// fiber terms) are not in the case.
inline constexpr const char *kDegenerateStartForcing =
    "backward Euler from a scramble, invert or collapse start, 3D solids (tetrahedra) with fiber terms or a volume "
    "term (nu > 0)";
inline constexpr OptionDecl newtonForcing =
    realOption("-newton_forcing", "eta",
               "inexact Newton: a linear solve may stop at relative residual eta while its step is still above 2x the "
               "tolerance; a certifying solve is always at -ksp_rtol (0: off)")
        .byDefault("0.01", kDegenerateStartForcing, "0", nullptr)
        .atLeast(0)
        .below(1);
inline constexpr OptionDecl liftIncrements =
    choiceOption("-lift_increments", "auto|always|never",
                 "the increment of the prescribed motion enters Newton's first linear solve, the interior moving with "
                 "its supports; auto: static steps, and backward Euler steps whose supports moved alone would fail "
                 "the alpha safeguard; never: supports move alone, the increment halved until the safeguard accepts it")
        .byDefault("auto");
inline constexpr OptionDecl newtonInertiaGuess =
    flagOption("-newton_inertia_guess",
               "beuler: the linear solve starts from the inertia-only step a M^-1 g (never worse than zero in the "
               "H-norm; exact for a rigid translation)")
        .byDefault("true");
inline constexpr OptionDecl nearNullspace =
    choiceOption("-near_nullspace", "rigid|none",
                 "the rest shape's rigid-body modes attached to the Jacobian as its near-nullspace (used by -pc_type "
                 "gamg; ignored by Jacobi and LU)")
        .byDefault("rigid");
inline constexpr OptionDecl multigridMinDofs =
    intOption("-multigrid_min_dofs", "N",
              "without -pc_type: a static solve with at least N free DoFs uses CG + GAMG (smoothed aggregation, rigid "
              "near-nullspace, AIJ), every other solve the paper's CG + Jacobi (-1: never GAMG); measured by "
              "bench/scale_out.py")
        .byDefault("200000")
        .atLeast(-1);

inline constexpr OptionDecl multigridReuseGrowth =
    realOption("-multigrid_reuse_growth", "g",
               "GAMG by the rule: up to 3 Newton systems share a multigrid hierarchy while each solve takes at most g "
               "times the iterations of its first (10 at least); a slower one stops and is repeated with a new one; 0: "
               "a new one for every system; -snes_lag_preconditioner turns it off")
        .byDefault("1.5")
        .atLeast(0);

inline constexpr const OptionDecl *kNewtonOptions[] = {
    &newtonTol,      &alphaMin,          &psdProjection,  &psdEigensystem,     &psdScope,     &psdAdaptiveTol,
    &newtonExactHessian, &newtonExactStart, &newtonSubspace,
    &newtonSubspaceMax, &newtonExtrapolate, &newtonLocalSolve, &newtonRotation, &newtonForcing,  &liftIncrements,
    &newtonInertiaGuess, &nearNullspace, &multigridMinDofs, &multigridReuseGrowth};

}  // namespace aries::solver::opt
