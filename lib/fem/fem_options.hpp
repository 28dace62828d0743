// The options of the discretization layer (material, boundary conditions, body forces, cloth terms), declared once
// (core/option_decl.hpp): the readers in lib/fem, `aries -help` and docs/options.md use these (the mesh's own:
// mesh/mesh_options.hpp). An energy's own parameters (-gamma, -beta, ...) are declared by its descriptor (energies/catalog/).
#pragma once

#include "core/option_decl.hpp"

namespace aries::fem::opt {

using core::choiceOption;
using core::flagOption;
using core::intOption;
using core::OptionDecl;
using core::realOption;
using core::realsOption;
using core::textOption;
using core::wordsOption;

// ---- material ----
inline constexpr OptionDecl energy =
    textOption("-energy", "NAME", "the energy density (table below); per region with -region_<id>_energy")
        .byDefault("bw46", "cloth", "iarap", nullptr);
inline constexpr OptionDecl youngsModulus =
    realOption("-E", "X", "Young's modulus; with -nu gives the Lame parameters mu, lambda").byDefault("1e4").above(0);
inline constexpr OptionDecl poissonRatio =
    realOption("-nu", "X", "Poisson's ratio").byDefault("0.3").atLeast(0).below(0.5);
inline constexpr OptionDecl lameMu =
    realOption("-mu", "X", "Lame mu directly (not with -E/-nu); -mu alone sets lambda = 0")
        .otherwise("from -E, -nu")
        .atLeast(0);
inline constexpr OptionDecl lameLambda =
    realOption("-lambda", "X", "Lame lambda directly (not with -E/-nu)").otherwise("from -E, -nu").atLeast(0);
inline constexpr OptionDecl clothStretch =
    realOption("-mu1", "X", "cloth stretch stiffness").byDefault("20");
inline constexpr OptionDecl clothShear =
    realOption("-mu2", "X", "cloth shear stiffness (energies with a shear term; bw46 has none)").byDefault("20");
inline constexpr OptionDecl fiber =
    realsOption("-fiber", "x,y,z",
                "fiber a in the material frame (2 numbers for planar and cloth elements); the basis u1 of ortho and "
                "kim_aa")
        .byDefault("1,0,0")
        .entries(3, 2);
inline constexpr OptionDecl fiber2 =
    realsOption("-fiber2", "x,y,z",
                "second fiber b (cloth) or second basis direction (ortho, kim_aa; orthogonalized against -fiber)")
        .byDefault("0,1,0")
        .entries(3, 2);
inline constexpr OptionDecl fiberFile =
    textOption("-fiber_file", "FILE", "per-cell fibers (format below); overrides -fiber").otherwise("none");
inline constexpr OptionDecl fiber2File =
    textOption("-fiber2_file", "FILE", "per-cell second fibers (cloth)").otherwise("none");
inline constexpr OptionDecl regions =
    wordsOption("-regions", "id,...",
                "gmsh volume groups (ids or names) with their own material: any material option per region as "
                "-region_<id>_<option>, starting from the global material")
        .otherwise("none");
inline constexpr OptionDecl activation =
    realsOption("-activation", "l1[,l2]",
                "shape_target: per-cell muscle-like target S_t = l1 a a^T + l2 (I - a a^T) along each cell's fiber, "
                "reached by the load ramp; l2 defaults to 1")
        .otherwise("none")
        .atLeast(0);
inline constexpr OptionDecl targetFile =
    textOption("-target_file", "FILE",
               "shape_target: per-cell keyframed targets, linear in time (format below); not with -target or "
               "-activation")
        .otherwise("none");

inline constexpr const OptionDecl *kMaterialOptions[] = {&energy, &youngsModulus, &poissonRatio, &lameMu,
                                                         &lameLambda, &clothStretch, &clothShear, &fiber,
                                                         &fiber2, &fiberFile, &fiber2File, &regions,
                                                         &activation, &targetFile};

// ---- singularity treatment (energies with I4/I6 terms) ----
inline constexpr OptionDecl singularity =
    choiceOption("-singularity", "none|mollifier|barrier",
                 "none: the raw closed-form I4/I6 (singular where alpha -> 0); mollifier: Eq. 33; barrier: Eq. 34 "
                 "added once per element")
        .byDefault("mollifier");
// The cases of the band's defaults (core::OptionDecl::when; docs/options.md, "The scale-free band"): the paper's band
// everywhere except where a 3D solid with anisotropic I4/I6 terms (energyHasAnisotropicStretchTerms) starts from a
// scramble, invert or collapse state: backward Euler, whose stretched inverted cells crawl towards I4's singular set
// above the paper's band (bench/results/degenerate_starts_scale_free.md), and static, where the paper's band left one
// start at a tangled minimum (bench/results/degenerate_starts_static_*scale_free*.md).
inline constexpr const char *kDegenerateStartBand =
    "a scramble, invert or collapse start, static or backward Euler, 3D solids with anisotropic I4/I6 terms";
inline constexpr const char *kScaleFreeBand = "scale_free";
inline constexpr OptionDecl mollifierMeasure =
    choiceOption("-mollifier_measure", "alpha|scale_free",
                 "what eps is measured in: alpha (Eq. 28, the paper) or alpha (I_C/C)^(-k/2), k = 3 (tets, cloth) or "
                 "1 (planar), equal to alpha at rest but independent of the stretch's scale (see below)")
        .byDefault("scale_free", kDegenerateStartBand, "alpha", nullptr);
inline constexpr OptionDecl mollifierEps =
    realOption("-mollifier_eps", "X", "threshold eps of Eq. 33 in -mollifier_measure's coordinate (blend on [eps, 3 eps])")
        .byDefault("0.3", kScaleFreeBand, "1e-3", nullptr)
        .above(0);
inline constexpr OptionDecl mollifierProxy =
    realOption("-mollifier_proxy", "X", "the constant proxy g = c of Eq. 33 (scaled by tr D for a fiber tensor D)")
        .byDefault("0");
inline constexpr OptionDecl barrierEps =
    realOption("-barrier_eps", "X", "eps of the aberration barrier (Eq. 34)").byDefault("1e-2").above(0);
inline constexpr OptionDecl barrierStiffness =
    realOption("-barrier_stiffness", "X", "kappa in kappa b(alpha)").otherwise("the energy's modulus (mu, mu1)").above(0);

inline constexpr const OptionDecl *kSingularityOptions[] = {&singularity, &mollifierEps, &mollifierMeasure, &mollifierProxy,
                                                            &barrierEps, &barrierStiffness};

// ---- boundary conditions ----
inline constexpr OptionDecl clamp =
    wordsOption("-bc_clamp", "id,...",
                "gmsh physical groups (numbers, or names from $PhysicalNames) whose vertices are prescribed")
        .otherwise("none");
inline constexpr OptionDecl clampTranslate =
    realsOption("-translate", "x,y,z", "total translation of the set, ramped linearly with the load parameter")
        .inFamily("-bc_clamp_<id>_")
        .byDefault("0,0,0")
        .entries(3);
inline constexpr OptionDecl clampRotate =
    realOption("-rotate", "deg", "total rotation angle of the set (degrees), ramped like the translation")
        .inFamily("-bc_clamp_<id>_")
        .byDefault("0");
inline constexpr OptionDecl clampAxis =
    realsOption("-axis", "x,y,z", "the rotation's axis (with -bc_clamp_<id>_rotate)")
        .inFamily("-bc_clamp_<id>_")
        .byDefault("0,0,1")
        .entries(3);
inline constexpr OptionDecl clampCenter =
    realsOption("-center", "x,y,z", "a point on the rotation's axis (with -bc_clamp_<id>_rotate)")
        .inFamily("-bc_clamp_<id>_")
        .otherwise("rest centroid of the set")
        .entries(3);
inline constexpr OptionDecl clampAffine =
    realsOption("-affine", "a11,...,a33",
                "a homogeneous deformation x = A X (about the origin, before the rotation and translation) the set "
                "follows, A row by row: 9 numbers (4 on a 2D mesh), ramped as X + s (A - I) X")
        .inFamily("-bc_clamp_<id>_")
        .otherwise("identity")
        .entries(9, 4);
inline constexpr OptionDecl clampComponents =
    wordsOption("-components", "x,y,z",
                "the components the set prescribes (symmetry planes, rollers: e.g. z, or x,y); the others stay free. "
                "A vertex in several sets is held in the union of their components, each by the first set listing it")
        .inFamily("-bc_clamp_<id>_")
        .byDefault("x,y,z");
inline constexpr OptionDecl boxes =
    realsOption("-bc_box", "xmin,xmax,ymin,ymax,zmin,zmax[,...]",
                "vertices inside box k (1-based, in the order given) are pinned at rest, or move by "
                "-bc_box_<k>_translate, _rotate, _axis, _center, _components like a clamp set (_surface: its boundary "
                "vertices only)")
        .otherwise("none");
inline constexpr OptionDecl boxSurface =
    flagOption("-surface",
               "box k holds only the vertices of the mesh's boundary facets inside it (a solid's surface: a handle "
               "that pushes the skin, not the body's interior; a sheet's or planar mesh's rim)")
        .inFamily("-bc_box_<k>_")
        .byDefault("false");
inline constexpr OptionDecl rampSteps =
    intOption("-bc_ramp_steps", "K", "load parameter s = min(1, step / K): the motion reaches its total after K steps")
        .otherwise("-steps")
        .atLeast(1);

inline constexpr const OptionDecl *kBoundaryOptions[] = {&clamp,       &clampTranslate, &clampRotate, &clampAxis,
                                                         &clampCenter, &clampAffine,    &clampComponents, &boxes,
                                                         &boxSurface,  &rampSteps};

// ---- body forces ----
inline constexpr OptionDecl density =
    realOption("-density", "X", "mass density (backward Euler's inertia, gravity)").byDefault("1000").above(0);
inline constexpr OptionDecl gravity =
    realsOption("-gravity", "gx,gy,gz", "gravitational acceleration (gx,gy on a 2D mesh)").byDefault("0,0,0").entries(3, 2);

inline constexpr const OptionDecl *kBodyForceOptions[] = {&density, &gravity};

// ---- surface loads: one option per boundary group, the group in the name (-load_traction_top) ----
inline constexpr OptionDecl loadTraction =
    realsOption("-", "tx,ty,tz",
                "dead traction (force per rest area) on the boundary group <set> (id or name: faces of a volume mesh, "
                "edges of a planar or cloth mesh), ramped with the load parameter (tx,ty on a 2D mesh)")
        .entries(3, 2)
        .otherwise("none")
        .inFamily("-load_traction_<set>");
inline constexpr OptionDecl loadForce =
    realsOption("-", "fx,fy,fz",
                "total dead force on the boundary group <set>, spread over it by rest area (the traction F / area), "
                "ramped with the load parameter (fx,fy on a 2D mesh)")
        .entries(3, 2)
        .otherwise("none")
        .inFamily("-load_force_<set>");

inline constexpr OptionDecl loadPressure =
    realOption("-", "p",
               "pressure on the boundary group <set> (faces of a volume mesh: P1 or P2 tetrahedra, hexahedra; edges "
               "of a planar mesh for a dead one), against the body's outward normal (p > 0 squeezes an outer "
               "surface, inflates a cavity), ramped with the load parameter; its kind below")
        .otherwise("none")
        .inFamily("-load_pressure_<set>");
inline constexpr OptionDecl loadPressureKind =
    choiceOption("-kind", "follower|dead",
                 "the pressure on <set>: follower (along the deformed surface's normal; a closed surface of a volume "
                 "mesh) or dead (-p N per rest area along the rest normal N; any surface, open or closed); a set name "
                 "cannot end in _kind")
        .byDefault("follower")
        .inFamily("-load_pressure_<set>_");

inline constexpr const OptionDecl *kLoadOptions[] = {&loadTraction, &loadForce, &loadPressure, &loadPressureKind};

// ---- cloth: bending and contact; planar orientation ----
inline constexpr OptionDecl bending =
    realOption("-bending", "k",
               "isometric quadratic bending (Bergou et al. 2006) on every interior edge of a flat-at-rest cloth")
        .byDefault("0")
        .atLeast(0);
inline constexpr OptionDecl obstaclePlanes =
    realsOption("-obstacle_plane", "px,py,pz,nx,ny,nz[,...]",
                "static planes: a point and the normal towards the free side, 6 numbers per plane")
        .otherwise("none");
inline constexpr OptionDecl obstacleSpheres =
    realsOption("-obstacle_sphere", "cx,cy,cz,r[,...]", "static spheres, 4 numbers per sphere").otherwise("none");
inline constexpr OptionDecl contactDhat =
    realOption("-contact_dhat", "d",
               "barrier activation distance: kappa b(d), b = -(d - dhat)^2 ln(d / dhat) for d < dhat (IPC style)")
        .otherwise("1e-2 x rest bounding-box diagonal")
        .above(0);
inline constexpr OptionDecl contactStiffness =
    realOption("-contact_stiffness", "kappa", "the barrier's stiffness (force / length)")
        .otherwise("mean vertex mass / dt^2 (beuler); modulus x h^(dim-2) (static)")
        .above(0);
inline constexpr OptionDecl keepOrientation =
    flagOption("-keep_orientation",
               "planar elements: the alpha safeguard also keeps det F > 0 in every element (no flipped triangle)")
        .byDefault("true", "uv_map", "false", nullptr);

inline constexpr const OptionDecl *kClothOptions[] = {&bending,     &obstaclePlanes,   &obstacleSpheres,
                                                      &contactDhat, &contactStiffness, &keepOrientation};

}  // namespace aries::fem::opt
