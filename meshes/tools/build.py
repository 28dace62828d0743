#!/usr/bin/python3
"""Builds the aries meshes of the catalog (tools/catalog.py: list, names, resolve). Called by meshes/generate.sh
(which owns the cache); usable directly:

    build.py build NAME SIZE OUTDIR    writes OUTDIR/NAME_SIZE.msh (+ NAME_SIZE.fibers for the octopus,
                                       NAME_SIZE.targets for the bunny)
                                       and OUTDIR/NAME_SIZE.json (statistics); log on stderr

Two kinds of mesh: tetrahedral volume meshes (cylinder, cube, armadillo, bunny, octopus,
triceratops, hand; z-up, every tet positively oriented and in a physical volume) and triangle
surface meshes in 3D (cloth, disk, lionhead, nefertiti; every triangle in a physical surface,
consistently oriented, boundary edges as physical curves). Outputs are deterministic: gmsh runs
single-threaded in a fixed sandbox with ASLR off (see GMSH_SANDBOX), and all post-processing is
plain numpy in a fixed order.
"""

import fcntl
import hashlib
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import meshkit as mk  # noqa: E402
import octopus as octo  # noqa: E402
import targets as tg  # noqa: E402
from catalog import CATALOG, CELL_KEY, kind, resolve, tube_cells  # noqa: E402

GEO = os.path.join(os.path.dirname(HERE), "geo")
GMSH = "/usr/bin/gmsh"  # fixed path: part of the reproducible argv (see GMSH_SANDBOX)
STEP_TIMEOUT = 600  # seconds, per external program run (generate.sh also bounds the whole build)

# Debian's CGAL data (package libcgal-demo). The same tarball is reachable from both doc dirs.
CGAL_DATA = [
    os.environ.get("ARIES_CGAL_DATA", ""),
    "/usr/share/doc/libcgal-dev/data.tar.gz",
    "/usr/share/doc/libcgal-demo/data.tar.gz",
]

def log(*a):
    print(*a, file=sys.stderr, flush=True)


def run(cmd, cwd, env=None, preexec_fn=None):
    """Run an external mesher; its output goes to the log (stderr). Fails loudly."""
    log("+ (cd %s && %s)" % (cwd, " ".join(cmd)))
    t = time.time()
    p = subprocess.run(cmd, cwd=cwd, env=env, preexec_fn=preexec_fn, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, timeout=STEP_TIMEOUT)
    errors = [l for l in p.stdout.splitlines() if l.startswith("Error")]
    if p.returncode != 0 or errors:
        log(p.stdout[-4000:])
        raise SystemExit("%s failed (exit %d)" % (cmd[0], p.returncode))
    log("  (%.1f s)" % (time.time() - t))


# gmsh 4.8 is not reproducible by default: some of its containers are ordered or hashed by pointer,
# so its output depends on the process's memory layout. Measured: with address-space layout
# randomisation (ASLR) on, every run of the octopus gives a different mesh (15,215 / 15,344 / 15,408
# tets ...); and the bunny, whose repeated runs in one directory happened to agree, gives 639,205 or
# 639,496 tets depending only on the directory it runs in (also on $HOME, the file names, the
# environment: string lengths shift the heap).
# So every gmsh run happens with ASLR off (setarch -R, util-linux), in the same fixed directory, with
# fixed file names, a fixed argv, a fixed minimal environment and a fixed stack limit, one at a time
# (file lock). With that, runs are byte-for-byte reproducible (checked across callers, directories
# and environments).
GMSH_SANDBOX = "/tmp/aries-meshgen"
GMSH_ENV = {"PATH": "/usr/bin:/bin", "HOME": GMSH_SANDBOX, "LC_ALL": "C"}
SETARCH = "/usr/bin/setarch"
GMSH_STACK = 8 << 20  # RLIMIT_STACK shapes the mmap layout too


def _setarch_works():
    try:
        return subprocess.run([SETARCH, "-R", "/bin/true"], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL).returncode == 0
    except OSError:
        return False


def _fixed_limits():
    try:
        resource.setrlimit(resource.RLIMIT_STACK, (GMSH_STACK, GMSH_STACK))
    except (ValueError, OSError):
        pass  # hard limit below 8 MiB: keep it (layout may then differ from other machines)


def gmsh_volume(geo_text, setnumbers, surface=None, order=1):
    """gmsh -3 on a .geo script (after merging the triangle surface (V, F), if given); returns the
    (X, T) of its tets (order 2: 10-node tets, gmsh's node order, edge nodes on the geometry). Runs in the fixed
    sandbox (see above)."""
    return gmsh_mesh(3, geo_text, setnumbers, surface, order)


def gmsh_mesh(dim, geo_text, setnumbers, surface=None, order=1):
    """gmsh -DIM on a .geo script (after merging the triangle surface (V, F), if given); returns the
    nodes and the tets (dim 3) or triangles (dim 2) of the result. Runs in the fixed sandbox."""
    reader = {3: mk.read_msh22_tets, 2: mk.read_msh22_tris}[dim]
    if order == 2:
        reader = {3: lambda path: mk.read_msh22_elements(path, mk.MSH_TET10, 10)}[dim]
    with open(GMSH_SANDBOX + ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        shutil.rmtree(GMSH_SANDBOX, ignore_errors=True)
        os.mkdir(GMSH_SANDBOX)
        try:
            with open(os.path.join(GMSH_SANDBOX, "model.geo"), "w") as f:
                f.write(geo_text)
            cmd = [GMSH, "-%d" % dim, "-nt", "1", "-format", "msh22", "-o", "out.msh"]
            if order != 1:
                cmd += ["-order", str(order)]
            if _setarch_works():
                cmd = [SETARCH, "-R"] + cmd
            else:
                log("WARNING: cannot disable ASLR here (setarch -R failed): gmsh output will not be "
                    "reproducible run to run")
            for k, v in setnumbers.items():
                cmd += ["-setnumber", k, repr(float(v))]
            if surface is not None:
                mk.write_surface_msh22(os.path.join(GMSH_SANDBOX, "surface.msh"), *surface)
                cmd.append("surface.msh")
            cmd.append("model.geo")
            run(cmd, GMSH_SANDBOX, env=GMSH_ENV, preexec_fn=_fixed_limits)
            return reader(os.path.join(GMSH_SANDBOX, "out.msh"))
        finally:
            shutil.rmtree(GMSH_SANDBOX, ignore_errors=True)


def read_geo(name):
    with open(os.path.join(GEO, name)) as f:
        return f.read()


# sha256 of the source surfaces in Debian 12's libcgal-demo 5.5.1-2 (a different file only warns)
SOURCE_SHA256 = {
    "data/meshes/armadillo.off": "6f7f3ca1abc506569466b72f2f59d49493a284e7376d7a7e23c08115ec8cec4e",
    "data/meshes/bunny00.off": "ab651cb04955c161efaeb079035a1e5e1f0e0d1f816a2df67beaea68f393ff2b",
    "data/meshes/triceratops.off": "0fb444933884486a09eb4329a832f15ab792590f2a5bb75385d157e654ddbf5c",
    "data/meshes/hand.off": "cfcf1562726167ca704a091a8651bfd1d72f6eb96b4b2819321f0520721b35c7",
    "data/meshes/camel.off": "9ac960a9fee27e6fcc6baaa2340260834625084ee20f4a97194212404e650a22",
    "data/meshes/bear.off": "058f6ce62635e5f86958adea9706a8dca3ebe4fae76a0d32b8318d107d40bda6",
    "data/meshes/bull.off": "5c7b9631f8c278c12b30c0eea0b72da871504674516daf7d7eaaf5fa4154224a",
    "data/meshes/homer.off": "99396cceb6f97e9681545d5c718d4ed87da3ceb78d22afb0218d570e9f0a0873",
    "data/meshes/lion-head.off": "cf159eeb12a3f3f345e57448693e9f0d115f3f6f38fd1d4519b336cede849289",
    "data/meshes/nefertiti.off": "d8b13239b988d0262fbc91e88da1d314eeb1b284c327a3fe76089c2b54886ccf",
}


def cgal_surface(member):
    for tar in CGAL_DATA:
        if tar and os.path.exists(tar):
            raw = mk.read_tar_member(tar, member)
            digest = hashlib.sha256(raw).hexdigest()
            if digest != SOURCE_SHA256.get(member):
                log("warning: %s:%s has sha256 %s, not the one these presets were tuned on"
                    % (tar, member, digest))
            V, F = mk.parse_off(raw)
            return V, F, tar
    raise SystemExit("CGAL data not found: install the Debian package libcgal-demo "
                     "(provides /usr/share/doc/libcgal-dev/data.tar.gz)")


# --------------------------------------------------------------------------------------------------
# Builders: params -> (TetMesh, extra files {suffix: writer(path)}, provenance dict)


def build_cylinder(p):
    m = mk.TetMesh(*gmsh_volume(read_geo("cylinder.geo"), {"h": p["h"]}))
    m.drop_unused_nodes()
    m.orient()
    F, _ = m.boundary_faces()
    z = m.X[F][:, :, 2]
    zmin, zmax = m.X[:, 2].min(), m.X[:, 2].max()
    tol = 1e-9 * (zmax - zmin)
    bottom = (np.abs(z - zmin) < tol).all(1)
    top = (np.abs(z - zmax) < tol).all(1)
    m.add_face_set(1, "bottom", F[bottom])
    m.add_face_set(2, "top", F[top])
    m.add_face_set(3, "side", F[~bottom & ~top])
    return m, {}, {"source": "gmsh OpenCASCADE cylinder, meshes/geo/cylinder.geo", "h": p["h"]}


def build_box(p):
    m = mk.TetMesh(*gmsh_volume(read_geo("box.geo"), {"h": p["h"]}))
    m.drop_unused_nodes()
    m.orient()
    F, _ = m.boundary_faces()
    z = m.X[F][:, :, 2]
    tol = 1e-9
    bottom = (np.abs(z) < tol).all(1)
    top = (np.abs(z - 2.0) < tol).all(1)
    m.add_face_set(1, "bottom", F[bottom])
    m.add_face_set(2, "top", F[top])
    m.add_face_set(3, "side", F[~bottom & ~top])
    return m, {}, {"source": "gmsh OpenCASCADE box 1 x 1 x 2, meshes/geo/box.geo", "h": p["h"]}


def build_shell(p, order=1):
    X, T = gmsh_volume(read_geo("shell.geo"), {"h": p["h"]}, order=order)
    m = mk.TetMesh(X, T) if order == 1 else mk.TetMesh.from_second_order(X, T)
    m.drop_unused_nodes()
    m.orient()
    F, _ = m.boundary_faces()
    r = np.linalg.norm(m.X[F].mean(1), axis=1)
    inner = r < 0.75
    m.add_face_set(1, "inner", F[inner])
    m.add_face_set(2, "outer", F[~inner])
    return m, {}, {"source": "gmsh OpenCASCADE sphere minus sphere, meshes/geo/shell.geo" +
                   (", gmsh -order 2 (edge nodes on the spheres)" if order == 2 else ""), "h": p["h"]}


def build_shell_curved(p):
    """build_shell's mesh (the same corners) with gmsh's second-order nodes: 10-node tets whose edge nodes on the
    inner and outer spheres lie on them (isoparametric P2 with -element p2)."""
    return build_shell(p, order=2)


def build_cube(p):
    """Unit cube, n^3 grid cells, each split into the 6 Freudenthal (Kuhn) tets around the main
    diagonal: conforming, all tets congruent, 6 n^3 tets (n = 18 gives the paper's 34,992)."""
    n = p["n"]
    g = np.linspace(0.0, 1.0, n + 1)
    zz, yy, xx = np.meshgrid(g, g, g, indexing="ij")  # node id = i + (n+1) (j + (n+1) k)
    X = np.c_[xx.ravel(), yy.ravel(), zz.ravel()]
    T = freudenthal_tets(n, n, n)  # cell-major: the 6 tets of grid cell 0, then cell 1, ...
    m = mk.TetMesh(X, T)
    m.orient()
    F, _ = m.boundary_faces()
    P = m.X[F]
    names = ["left", "right", "front", "back", "bottom", "top"]
    for tag, name in enumerate(names, start=1):
        axis, val = (tag - 1) // 2, float((tag - 1) % 2)
        m.add_face_set(tag, name, F[(np.abs(P[:, :, axis] - val) < 1e-12).all(1)])
    m.add_face_set(7, "surface", F)  # the whole closed boundary (a pressure on every face)
    return m, {}, {"source": "structured Freudenthal subdivision (meshes/tools/build.py)", "n": n}


def build_hexcube(p):
    """Unit cube as an n^3 grid of trilinear hexahedra, face sets left/right/front/back/bottom/top (quadrangles);
    with 'jitter', every interior node moves by up to jitter * (1/n) in each coordinate (seeded: deterministic), so
    the cells are general trilinear hexahedra (non-planar faces), not parallelepipeds (patch tests)."""
    n = p["n"]
    g = np.linspace(0.0, 1.0, n + 1)
    zz, yy, xx = np.meshgrid(g, g, g, indexing="ij")  # node id = i + (n+1) (j + (n+1) k)
    X = np.c_[xx.ravel(), yy.ravel(), zz.ravel()]
    if p.get("jitter"):
        interior = ((X > 1e-12) & (X < 1 - 1e-12)).all(1)
        rng = np.random.default_rng(20261126)
        X[interior] += p["jitter"] / n * rng.uniform(-1.0, 1.0, (int(interior.sum()), 3))
    m = mk.HexMesh(X, mk.grid_hexes(np.ones((n, n, n), dtype=bool)))
    F, _ = m.boundary_faces()
    P = m.X[F]
    for tag, name in enumerate(["left", "right", "front", "back", "bottom", "top"], start=1):
        axis, val = (tag - 1) // 2, float((tag - 1) % 2)
        m.add_face_set(tag, name, F[(np.abs(P[:, :, axis] - val) < 1e-12).all(1)])
    m.add_face_set(7, "surface", F)  # the whole closed boundary (a pressure on every face)
    return m, {}, {"source": "structured grid (meshes/tools/build.py)", "n": n, "jitter": p.get("jitter", 0.0)}


def voxel_volume(V, F, h):
    """The voxels of edge h whose centres lie inside the closed surface (V, F), on a grid over its bounding box, as a
    hexahedral mesh (staircase boundary), its boundary quadrangles as face set 1 "surface"."""
    lo, hi = V.min(0), V.max(0)
    n = np.ceil((hi - lo) / h).astype(int) + 2
    origin = 0.5 * (lo + hi) - 0.5 * h * n
    centres = [origin[a] + h * (np.arange(n[a]) + 0.5) for a in range(3)]
    mask = mk.inside_closed_surface_columns(V, F, *centres)
    # keep the largest face-connected component (a voxel touching the rest by an edge only would hang loose)
    lab = -np.ones(mask.shape, dtype=np.int64)
    comp = 0
    sizes = []
    for seed in zip(*np.nonzero(mask)):
        if lab[seed] >= 0:
            continue
        stack, lab[seed], count = [seed], comp, 0
        while stack:
            c = stack.pop()
            count += 1
            for a in range(3):
                for dlt in (-1, 1):
                    q = list(c)
                    q[a] += dlt
                    q = tuple(q)
                    if 0 <= q[a] < n[a] and mask[q] and lab[q] < 0:
                        lab[q] = comp
                        stack.append(q)
        sizes.append(count)
        comp += 1
    mask &= lab == int(np.argmax(sizes))
    gx, gy, gz = [origin[a] + h * np.arange(n[a] + 1) for a in range(3)]
    zz, yy, xx = np.meshgrid(gz, gy, gx, indexing="ij")
    m = mk.HexMesh(np.c_[xx.ravel(), yy.ravel(), zz.ravel()], mk.grid_hexes(mask))
    m.drop_unused_nodes()
    Fb, _ = m.boundary_faces()
    m.add_face_set(1, "surface", Fb)
    return m


def remeshed_surface_volume(V, F, h):
    """Remesh a closed triangle surface with gmsh at uniform size h and fill it with tets
    (meshes/geo/remesh.geo)."""
    return gmsh_volume(read_geo("remesh.geo"), {"h": h}, surface=(V, F))


def checked_surface(member, scale):
    V, F, tar = cgal_surface(member)
    chi, _ = mk.check_closed_manifold(F, len(V))
    if chi != 2:
        raise SystemExit("%s: Euler characteristic %d (expected a closed genus-0 surface)" % (member, chi))
    # source files are y-up; rotate +90 deg about x to z-up: (x, y, z) -> (x, -z, y) (a proper rotation)
    V = scale * np.c_[V[:, 0], -V[:, 2], V[:, 1]]
    if mk.surface_volume(V, F) <= 0:
        F = F[:, ::-1].copy()
    log("source %s:%s  %d vertices, %d triangles, closed, Euler characteristic 2, volume %.6g"
        % (tar, member, len(V), len(F), mk.surface_volume(V, F)))
    return V, F, tar


# Armadillo: hands and feet. Four anchor points, found on the tet mesh's own vertices (z-up, scaled
# coordinates; the remeshed surface rounds off the thin claws, so anchors taken on the dense scan
# could lie outside a coarse mesh):
#   hands: the claw tips = the vertex of largest y (the claws point forward, +y) among x < -0.3
#          (left) and among x > +0.3 (right);
#   feet:  the sole centres = the mean of the vertices with z < zmin(side) + 0.02 among x < 0 and
#          among x >= 0, where zmin(side) is the lowest z on that side.
# Every mesh vertex within ARMADILLO_PIN_RADIUS of an anchor is pinned (tag 10 "hands_feet").
ARMADILLO_SCALE = 0.01
ARMADILLO_PIN_RADIUS = 0.08


def armadillo_anchors(V):
    x, y, z = V.T
    anchors = {}
    for side, mask in (("left", x < -0.3), ("right", x > 0.3)):
        idx = np.flatnonzero(mask)
        anchors["hand_" + side] = V[idx[np.argmax(y[idx])]]
    for side, mask in (("left", x < 0), ("right", x >= 0)):
        idx = np.flatnonzero(mask)
        sole = idx[z[idx] < z[idx].min() + 0.02]
        anchors["foot_" + side] = V[sole].mean(0)
    return anchors


def build_armadillo(p):
    V, F, tar = checked_surface("data/meshes/armadillo.off", ARMADILLO_SCALE)
    m = mk.TetMesh(*remeshed_surface_volume(V, F, p["h"]))
    m.drop_unused_nodes()
    m.orient()
    anchors = armadillo_anchors(m.X)
    pinned = np.zeros(len(m.X), dtype=bool)
    per = {}
    for key, a in anchors.items():
        near = np.linalg.norm(m.X - a, axis=1) < ARMADILLO_PIN_RADIUS
        per[key] = int(near.sum())
        pinned |= near
    m.add_vertex_set(10, "hands_feet", np.flatnonzero(pinned))
    log("hands_feet: %d vertices (%.2f%%), per extremity %s"
        % (pinned.sum(), 100.0 * pinned.mean(), per))
    return m, {}, {
        "source": tar + ":data/meshes/armadillo.off",
        "transform": "scaled by %g, rotated y-up -> z-up: (x,y,z) -> (x,-z,y)" % ARMADILLO_SCALE,
        "h": p["h"],
        "pin_radius": ARMADILLO_PIN_RADIUS,
        "anchors": {k: [round(float(c), 6) for c in a] for k, a in anchors.items()},
        "pinned_per_extremity": per,
    }


def build_bunny(p):
    V, F, tar = checked_surface("data/meshes/bunny00.off", 1.0)
    if "voxel" in p:  # the paper's Fig. 13 runs on hexahedra: voxels of the closed surface
        m = voxel_volume(V, F, p["voxel"])
        cells = m.T
    else:
        m = mk.TetMesh(*remeshed_surface_volume(V, F, p["h"]))
        m.drop_unused_nodes()
        m.orient()
        Fb, _ = m.boundary_faces()
        m.add_face_set(1, "surface", Fb)
        cells = m.T
    comments = ["aries shape-target keyframes (-target_file) for the bunny's guided performance (paper Fig. 13),",
                "generated by meshes/tools/targets.py from the rest geometry; one target per cell in .msh order."]
    frames = tg.bunny_guided_keyframes(m.X, cells)
    extra = {".targets": lambda path: tg.write_keyframes(path, frames, comments)}
    return m, extra, {
        "source": tar + ":data/meshes/bunny00.off",
        "transform": "rotated y-up -> z-up: (x,y,z) -> (x,-z,y)",
        "h": p.get("h"), "voxel": p.get("voxel"),
    }


# Closed CGAL surfaces the paper's scenes do not use, to run the solver on unfamiliar shapes. Both
# are checked like the armadillo and bunny (closed, edge-manifold, Euler characteristic 2, outward),
# scaled to a bounding-box diagonal of ~1.4-1.6, rotated y-up -> z-up and remeshed the same way.
# Only the physical volume 1 "body": no boundary groups (pin with -bc_box).
#   triceratops: a standing quadruped (horns, frill, tapering tail), source units ~18 long;
#   hand: a clenched fist cut flat at the wrist, source already normalised to a largest extent of 1.
TRICERATOPS_SCALE = 0.07
HAND_SCALE = 1.0
CAMEL_SCALE = 1.05
BEAR_SCALE = 1.0
BULL_SCALE = 1.6   # source largest extent 1 (its length): 1.6 x 1.09 x 1.28 after scaling
HOMER_SCALE = 1.6  # source largest extent 1 (its height): 0.90 x 0.52 x 1.6 after scaling


def build_cgal_solid(member, scale, p):
    V, F, tar = checked_surface(member, scale)
    if "voxel" in p:  # voxel hexahedra of the closed surface, as the bunny's hex sizes
        m = voxel_volume(V, F, p["voxel"])
    else:
        m = mk.TetMesh(*remeshed_surface_volume(V, F, p["h"]))
        m.drop_unused_nodes()
        m.orient()
    return m, {}, {
        "source": tar + ":" + member,
        "transform": "scaled by %g, rotated y-up -> z-up: (x,y,z) -> (x,-z,y)" % scale,
        **({"voxel": p["voxel"]} if "voxel" in p else {"h": p["h"]}),
    }


def build_triceratops(p):
    return build_cgal_solid("data/meshes/triceratops.off", TRICERATOPS_SCALE, p)


def build_hand(p):
    return build_cgal_solid("data/meshes/hand.off", HAND_SCALE, p)


def build_camel(p):
    return build_cgal_solid("data/meshes/camel.off", CAMEL_SCALE, p)


def build_bear(p):
    return build_cgal_solid("data/meshes/bear.off", BEAR_SCALE, p)


def build_bull(p):
    return build_cgal_solid("data/meshes/bull.off", BULL_SCALE, p)


def build_homer(p):
    return build_cgal_solid("data/meshes/homer.off", HOMER_SCALE, p)


def build_octopus(p):
    m = mk.TetMesh(*gmsh_volume(octo.geo_text(), {"hmax": p["hmax"], "ncurv": p["ncurv"]}))
    m.drop_unused_nodes()
    m.orient()
    centroids = m.X[m.T].mean(1)
    tentacle, fibers = octo.classify_cells(centroids)
    m.set_region(2, "tentacles", tentacle >= 0)
    top = octo.top_vertices(m.X)
    m.add_vertex_set(10, "top", top)
    counts = np.bincount(tentacle[tentacle >= 0], minlength=octo.N_TENTACLES)
    log("octopus: tentacle tets per arm %s, top vertices %d" % (counts.tolist(), len(top)))
    comments = [
        "aries per-cell fiber directions for the octopus mesh (unit vectors, one per tetrahedron,",
        "in the order of the tetrahedra in the .msh file = PETSc serial cell order).",
        "Tentacle tets (Cell Sets 2): tangent of their tentacle's centerline at the nearest point,",
        "pointing from the head to the tip. Body tets (Cell Sets 1): (0, 0, 1), not stiffened.",
    ]
    extra = {".fibers": lambda path: mk.write_cell_vectors(path, fibers, comments)}
    return m, extra, {"source": "gmsh OpenCASCADE, meshes/tools/octopus.py", "hmax": p["hmax"],
                      "ncurv": p["ncurv"], "tets_per_tentacle": counts.tolist(),
                      "parameters": octo.PARAMS}


# --------------------------------------------------------------------------------------------------
# Triangle surface meshes: params -> (TriMesh, extra files, provenance)


def build_cloth(p):
    """Unit square [0,1]^2 in the plane z = 0, n x n grid squares, each split along its (+1,+1)
    diagonal into 2 triangles (the same diagonal everywhere): 2 n^2 triangles, normals +z.
    Node (i, j) = (i/n, j/n, 0) is node i + (n+1) j (x fastest). Square (i, j) with corners
    a = (i,j), b = (i+1,j), c = (i+1,j+1), d = (i,j+1) gives triangles (a, b, c) then (a, c, d);
    squares in row-major order (i fastest, then j)."""
    n = p["n"]
    g = np.linspace(0.0, 1.0, n + 1)
    yy, xx = np.meshgrid(g, g, indexing="ij")
    X = np.c_[xx.ravel(), yy.ravel(), np.zeros(xx.size)]
    T = grid_triangles(n, n)
    m = mk.TriMesh(X, T, name="cloth")
    if m.orient_consistently() or m.orient_up((0.0, 0.0, 1.0)):
        raise SystemExit("cloth: triangles not generated +z oriented (bug)")
    (loop,) = m.boundary_loops()  # counter-clockwise from node 0 = (0,0): bottom, right, top, left
    P = m.X[loop]  # (k, 2 endpoints, 3)
    for tag, name, axis, val in ((1, "left", 0, 0.0), (2, "right", 0, 1.0),
                                 (3, "bottom", 1, 0.0), (4, "top", 1, 1.0)):
        m.add_edge_set(tag, name, loop[(np.abs(P[:, :, axis] - val) < 1e-12).all(1)])
    corner = lambda x, y: int(np.argmin(np.abs(m.X[:, 0] - x) + np.abs(m.X[:, 1] - y)))
    m.add_vertex_set(11, "corner_00", [corner(0, 0)])
    m.add_vertex_set(12, "corner_10", [corner(1, 0)])
    m.add_vertex_set(13, "corner_01", [corner(0, 1)])
    m.add_vertex_set(14, "corner_11", [corner(1, 1)])
    m.add_vertex_set(15, "top_corners", [corner(0, 1), corner(1, 1)])
    return m, {}, {"source": "structured grid (meshes/tools/build.py)", "n": n,
                   "diagonal": "every grid square split along its (0,0)-(1,1) diagonal (direction [1,1])"}


def grid_triangles(nx, ny):
    """The triangles of an nx x ny grid of nodes i + (nx+1) j (i fastest): cell (i, j) with corners a = (i,j),
    b = (i+1,j), c = (i+1,j+1), d = (i,j+1) gives (a, b, c) then (a, c, d); cells in row-major order (i fastest)."""
    N = nx + 1
    j, i = np.meshgrid(np.arange(ny), np.arange(nx), indexing="ij")
    a = (i + N * j).ravel()
    b, c, d = a + 1, a + 1 + N, a + N
    return np.stack([np.c_[a, b, c], np.c_[a, c, d]], 1).reshape(-1, 3)


def build_beam(p):
    """A cantilever [0,10] x [0,1] in the plane z = 0: nx x nx/10 square cells, each split along its (0,0)-(1,1)
    diagonal (2 nx^2 / 10 triangles). Edge groups: left (x = 0, the clamp) and right (x = 10, the end load)."""
    nx = p["nx"]
    ny = nx // 10
    gx, gy = np.linspace(0.0, 10.0, nx + 1), np.linspace(0.0, 1.0, ny + 1)
    yy, xx = np.meshgrid(gy, gx, indexing="ij")
    X = np.c_[xx.ravel(), yy.ravel(), np.zeros(xx.size)]
    T = grid_triangles(nx, ny)
    m = mk.TriMesh(X, T, name="beam")
    if m.orient_consistently() or m.orient_up((0.0, 0.0, 1.0)):
        raise SystemExit("beam: triangles not generated +z oriented (bug)")
    (loop,) = m.boundary_loops()
    E = m.X[loop]
    m.add_edge_set(1, "left", loop[(np.abs(E[:, :, 0]) < 1e-9).all(1)])
    m.add_edge_set(2, "right", loop[(np.abs(E[:, :, 0] - 10.0) < 1e-9).all(1)])
    return m, {}, {"source": "structured grid (meshes/tools/build.py)", "nx": nx}


def freudenthal_tets(nx, ny, nz):
    """The tets of an nx x ny x nz grid of nodes i + (nx+1) (j + (ny+1) k): each cell split into the 6 Freudenthal
    (Kuhn) tets around its main diagonal (conforming across cells), cell-major."""
    Nx, Ny = nx + 1, ny + 1
    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    base = (i + Nx * (j + Ny * k)).ravel()
    step = {0: 1, 1: Nx, 2: Nx * Ny}
    tets = []
    for perm, even in (([0, 1, 2], True), ([0, 2, 1], False), ([1, 0, 2], False),
                       ([1, 2, 0], True), ([2, 0, 1], True), ([2, 1, 0], False)):
        b = base + step[perm[0]]
        c = b + step[perm[1]]
        d = c + step[perm[2]]
        tets.append(np.stack([base, b, c, d] if even else [base, b, d, c], 1))
    return np.stack(tets, 1).reshape(-1, 4)


def cook_panel_points(n):
    """The (n+1)^2 nodes i + (n+1) j of Cook's panel: the bilinear map of the unit square's n x n grid onto the
    quadrilateral (0,0), (48,44), (48,60), (0,44) (x, y)."""
    g = np.linspace(0.0, 1.0, n + 1)
    eta, xi = np.meshgrid(g, g, indexing="ij")
    xi, eta = xi.ravel(), eta.ravel()
    corners = np.array([[0.0, 0.0], [48.0, 44.0], [48.0, 60.0], [0.0, 44.0]])
    return (np.outer((1 - xi) * (1 - eta), corners[0]) + np.outer(xi * (1 - eta), corners[1])
            + np.outer(xi * eta, corners[2]) + np.outer((1 - xi) * eta, corners[3]))


def build_cook_slab(p):
    """Cook's membrane as a 3D slab: the panel of build_cook (n x n cells of the bilinear map) extruded over
    z in [0, 1/2], the upper half of a slab 1 thick (one cell layer, 6 Freudenthal tets per cell: 6 n^2 tets). Face
    groups: left (x = 0, clamped in x, y), right (x = 48, the shear load), mid (z = 0, the symmetry plane: held in z)
    and top (z = 1/2, free)."""
    n = p["n"]
    P = cook_panel_points(n)
    layers = np.repeat([0.0, 0.5], len(P))  # node i + (n+1) (j + (n+1) k): the panel at z = 0, then at z = 1/2
    m = mk.TetMesh(np.c_[np.vstack([P, P]), layers], freudenthal_tets(n, n, 1))
    m.orient()
    F, _ = m.boundary_faces()
    Q = m.X[F]
    for tag, name, axis, value in ((1, "left", 0, 0.0), (2, "right", 0, 48.0), (3, "mid", 2, 0.0), (4, "top", 2, 0.5)):
        m.add_face_set(tag, name, F[(np.abs(Q[:, :, axis] - value) < 1e-9).all(1)])
    return m, {}, {"source": "structured bilinear map, extruded (meshes/tools/build.py)", "n": n}


def build_cook_slab_full(p):
    """The whole slab of build_cook_slab, z in [-1/2, 1/2]: its half and the half's mirror image in z = 0 (two cell
    layers, 12 n^2 tets), so the half with its symmetry plane held in z is this body's upper half exactly: a reference
    for the symmetry support. Face groups: left, right, top (z = 1/2), bottom (z = -1/2)."""
    n = p["n"]
    P = cook_panel_points(n)
    layers = np.repeat([-0.5, 0.0, 0.5], len(P))  # the panel at z = -1/2, 0, 1/2
    upper = freudenthal_tets(n, n, 1) + len(P)  # build_cook_slab's tets on the layers z = 0, 1/2
    lower = np.where(upper < 2 * len(P), upper, upper - 2 * len(P))  # z = 1/2 -> -1/2: the mirror image
    m = mk.TetMesh(np.c_[np.vstack([P, P, P]), layers], np.vstack([upper, lower]))
    m.orient()
    F, _ = m.boundary_faces()
    Q = m.X[F]
    for tag, name, axis, value in ((1, "left", 0, 0.0), (2, "right", 0, 48.0), (3, "bottom", 2, -0.5),
                                   (4, "top", 2, 0.5)):
        m.add_face_set(tag, name, F[(np.abs(Q[:, :, axis] - value) < 1e-9).all(1)])
    return m, {}, {"source": "structured bilinear map, extruded and mirrored (meshes/tools/build.py)", "n": n}


def build_cook_hex(p):
    """build_cook_slab's panel and face groups in trilinear hexahedra: n x n x 1 cells of the extruded bilinear map."""
    n = p["n"]
    P = cook_panel_points(n)
    layers = np.repeat([0.0, 0.5], len(P))
    m = mk.HexMesh(np.c_[np.vstack([P, P]), layers], mk.grid_hexes(np.ones((n, n, 1), dtype=bool)))
    F, _ = m.boundary_faces()
    Q = m.X[F]
    for tag, name, axis, value in ((1, "left", 0, 0.0), (2, "right", 0, 48.0), (3, "mid", 2, 0.0), (4, "top", 2, 0.5)):
        m.add_face_set(tag, name, F[(np.abs(Q[:, :, axis] - value) < 1e-9).all(1)])
    return m, {}, {"source": "structured bilinear map, extruded (meshes/tools/build.py)", "n": n}


def tube_points(n):
    """The nodes i + (n+1) (j + (m+1) k) of the quarter tube: radius 1 + i / n, angle (pi/2) j / m, z = k / n for
    k = 0, 1 (m = tube_cells(n)); every node on its circle (the hexahedra's edges across it are straight chords)."""
    m = tube_cells(n)
    k, j, i = np.meshgrid(np.arange(2), np.arange(m + 1), np.arange(n + 1), indexing="ij")
    r, t = 1.0 + i.ravel() / n, 0.5 * math.pi * j.ravel() / m
    return np.c_[r * np.cos(t), r * np.sin(t), k.ravel() / n], m


def tube_face_sets(m, F, n):
    """inner (r = 1), outer (r = 2), xzero (x = 0), yzero (y = 0), bottom (z = 0), top (z = 1 / n)."""
    Q = m.X[F]
    r = np.linalg.norm(Q[:, :, :2], axis=2)
    for tag, name, on in ((1, "inner", np.abs(r - 1.0) < 1e-9), (2, "outer", np.abs(r - 2.0) < 1e-9),
                          (3, "xzero", np.abs(Q[:, :, 0]) < 1e-9), (4, "yzero", np.abs(Q[:, :, 1]) < 1e-9),
                          (5, "bottom", np.abs(Q[:, :, 2]) < 1e-9), (6, "top", np.abs(Q[:, :, 2] - 1.0 / n) < 1e-9)):
        m.add_face_set(tag, name, F[on.all(1)])


def build_shell_hex(p):
    """Lame's thick sphere (inner radius 0.5, outer 1) as a cubed sphere of trilinear hexahedra: each face of the cube
    [-1, 1]^3 an n x n grid of equal angles (tan map), projected on the spheres of n / 2 + 1 radii evenly spaced from
    0.5 to 1; corners shared across faces (merged). Face groups inner, outer."""
    n, layers = p["n"], p["n"] // 2
    t = np.tan(np.linspace(-math.pi / 4, math.pi / 4, n + 1))
    radii = np.linspace(0.5, 1.0, layers + 1)
    points, cells = [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            v, u = np.meshgrid(t, t, indexing="ij")
            cube = np.zeros((n + 1, n + 1, 3))
            cube[..., axis] = sign
            cube[..., (axis + 1) % 3] = u
            cube[..., (axis + 2) % 3] = v
            unit = cube / np.linalg.norm(cube, axis=2, keepdims=True)
            base = sum(len(q) for q in points)
            points.append((radii[:, None, None, None] * unit[None]).reshape(-1, 3))  # (k, j, i) with i fastest
            node = lambda i, j, k: base + i + (n + 1) * (j + (n + 1) * k)
            k, j, i = np.meshgrid(np.arange(layers), np.arange(n), np.arange(n), indexing="ij")
            i, j, k = i.ravel(), j.ravel(), k.ravel()
            cells.append(np.stack([node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                                   node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1),
                                   node(i, j + 1, k + 1)], axis=1))
    X = np.vstack(points)
    H = np.vstack(cells)
    # merge the copies of the nodes on the cube's edges (equal up to round-off)
    key = np.round(X * 1e9).astype(np.int64)
    _, first, inverse = np.unique(key, axis=0, return_index=True, return_inverse=True)
    H = first[inverse.ravel()][H]
    # positive numbering: a cell with negative corner Jacobians swaps its two layers' faces' orientation
    neg = mk.hex_jacobians(X, H).min(1) < 0
    H[neg] = H[neg][:, [0, 3, 2, 1, 4, 7, 6, 5]]
    m = mk.HexMesh(X, H)
    m.drop_unused_nodes()
    if (mk.hex_jacobians(m.X, m.T) <= 0).any():
        raise SystemExit("shell_hex: a cell is not positively numbered (bug)")
    F, _ = m.boundary_faces()
    r = np.linalg.norm(m.X[F].mean(1), axis=1)
    m.add_face_set(1, "inner", F[r < 0.75])
    m.add_face_set(2, "outer", F[r >= 0.75])
    return m, {}, {"source": "cubed sphere (meshes/tools/build.py)", "n": n}


def build_tube(p):
    """Lame's thick cylinder (inner radius 1, outer 2) in plane strain, the quarter x, y >= 0, one cell layer
    z in [0, 1/n]: n cells across the wall, tube_cells(n) around, each cell split into 6 Freudenthal tets. Face groups
    in tube_face_sets (the symmetry planes xzero, yzero and the ends bottom, top carry rollers in the benchmark)."""
    n = p["n"]
    X, m_ = tube_points(n)
    m = mk.TetMesh(X, freudenthal_tets(n, m_, 1))
    m.orient()
    F, _ = m.boundary_faces()
    tube_face_sets(m, F, n)
    return m, {}, {"source": "structured quarter annulus (meshes/tools/build.py)", "n": n}


def build_tube_curved(p):
    """build_tube's tets (the same corners) with a node on every edge at the middle in (r, angle, z): every edge
    along a circle is an arc of it, so the inner and outer walls are exact to second order (isoparametric P2)."""
    m, groups, info = build_tube(p)
    E = np.unique(np.sort(m.T[:, mk.TET10_EDGES].reshape(-1, 2), axis=1), axis=0)
    P = m.X[E]  # (k, 2, 3)
    r, t = np.linalg.norm(P[:, :, :2], axis=2).mean(1), np.arctan2(P[:, :, 1], P[:, :, 0]).mean(1)
    m.set_edge_nodes(E, np.c_[r * np.cos(t), r * np.sin(t), P[:, :, 2].mean(1)])
    info["source"] += ", edge nodes at the middle in polar coordinates"
    return m, groups, info


def build_tube_hex(p):
    """build_tube's quarter in trilinear hexahedra (n x tube_cells(n) x 1), the same face groups."""
    n = p["n"]
    X, m_ = tube_points(n)
    m = mk.HexMesh(X, mk.grid_hexes(np.ones((n, m_, 1), dtype=bool)))
    F, _ = m.boundary_faces()
    tube_face_sets(m, F, n)
    return m, {}, {"source": "structured quarter annulus (meshes/tools/build.py)", "n": n}


def build_cook(p):
    """Cook's membrane (Cook 1974; the plane-stress benchmark of e.g. Simo & Rifai 1990): the quadrilateral panel with
    corners (0,0), (48,44), (48,60), (0,44) in the plane z = 0, an n x n grid of the bilinear map of the unit square,
    each cell split along its (0,0)-(1,1) diagonal: 2 n^2 triangles, normals +z. Edge groups: left (x = 0, clamped in
    the benchmark) and right (x = 48, the shear load); vertex groups mid_edge = (48, 52), the loaded edge's midpoint,
    where the benchmark reads the vertical displacement (its reference 23.96), and tip = (48, 60), the top corner."""
    n = p["n"]
    P = cook_panel_points(n)
    X = np.c_[P, np.zeros(len(P))]
    T = grid_triangles(n, n)
    m = mk.TriMesh(X, T, name="panel")
    if m.orient_consistently() or m.orient_up((0.0, 0.0, 1.0)):
        raise SystemExit("cook: triangles not generated +z oriented (bug)")
    (loop,) = m.boundary_loops()
    E = m.X[loop]
    m.add_edge_set(1, "left", loop[(np.abs(E[:, :, 0]) < 1e-9).all(1)])
    m.add_edge_set(2, "right", loop[(np.abs(E[:, :, 0] - 48.0) < 1e-9).all(1)])
    m.add_vertex_set(11, "tip", [int(np.argmin(np.abs(m.X[:, 0] - 48.0) + np.abs(m.X[:, 1] - 60.0)))])
    m.add_vertex_set(12, "mid_edge", [int(np.argmin(np.abs(m.X[:, 0] - 48.0) + np.abs(m.X[:, 1] - 52.0)))])
    return m, {}, {"source": "structured bilinear map (meshes/tools/build.py)", "n": n}


DISK_AMPLITUDE = 0.15


def build_disk(p):
    """Wavy disk: the graph z = 0.15 sin(3x) cos(2y) over the unit disk x^2 + y^2 <= 1.
    Concentric rings: node 0 is the centre, ring k = 1..R has 6k nodes at radius k/R and angles
    2 pi j / (6k), j = 0..6k-1 (counter-clockwise, j = 0 on +x). The strip between rings k-1 and k
    has 6(2k-1) triangles (per sextant s: for t = 0..k-1 the triangle (o_t, o_t+1, i_t) and for
    t < k-1 (i_t, o_t+1, i_t+1), o/i = outer/inner ring nodes of the sextant), so 6 R^2 triangles,
    all with upward (+z component) normals. Every triangle near-equilateral in the xy projection."""
    R = p["rings"]
    start = [0, 1]
    for k in range(1, R + 1):
        start.append(start[-1] + 6 * k)
    xy = [np.zeros((1, 2))]
    for k in range(1, R + 1):
        t = 2.0 * np.pi * np.arange(6 * k) / (6 * k)
        xy.append((k / R) * np.c_[np.cos(t), np.sin(t)])
    xy = np.concatenate(xy)
    X = np.c_[xy, DISK_AMPLITUDE * np.sin(3.0 * xy[:, 0]) * np.cos(2.0 * xy[:, 1])]
    T = []
    for k in range(1, R + 1):
        for s in range(6):
            o = lambda t: start[k] + (s * k + t) % (6 * k)
            inner = (lambda t: 0) if k == 1 else (lambda t: start[k - 1] + (s * (k - 1) + t) % (6 * (k - 1)))
            for t in range(k):
                T.append((o(t), o(t + 1), inner(t)))
                if t < k - 1:
                    T.append((inner(t), o(t + 1), inner(t + 1)))
    m = mk.TriMesh(X, np.array(T, dtype=np.int64))
    if m.orient_consistently() or m.orient_up((0.0, 0.0, 1.0)):
        raise SystemExit("disk: triangles not generated consistently upward (bug)")
    if (m.area_vectors()[:, 2] <= 0).any():
        raise SystemExit("disk: a triangle normal points down (bug)")
    m.check_disk("disk")
    (loop,) = m.boundary_loops()
    m.add_edge_set(1, "boundary", loop)
    return m, {}, {"source": "concentric-ring triangulation of the unit disk (meshes/tools/build.py)",
                   "surface": "z = %g sin(3x) cos(2y) over x^2 + y^2 <= 1" % DISK_AMPLITUDE,
                   "rings": R}


def cgal_disk(member):
    """A CGAL open surface, checked to be a manifold disk: cleaned (unreferenced vertices, repeated
    or degenerate triangles dropped), consistently oriented with normals pointing out of the shape
    closed up at its boundary, then centred (bounding-box centre to the origin) and scaled uniformly
    to a largest bounding-box extent of 1. Axes are kept (the faces look along +z, y is up)."""
    V, F, tar = cgal_surface(member)
    m = mk.TriMesh(V, F)
    degen, dup = m.drop_bad_triangles()
    unused = m.drop_unused_nodes()
    before = m.topology()
    flipped = m.orient_consistently()
    outward_flip = m.orient_outward()
    t = m.check_disk(member)
    lo, hi = m.X.min(0), m.X.max(0)
    centre = 0.5 * (lo + hi)
    scale = 1.0 / float((hi - lo).max())
    m.X = (m.X - centre) * scale
    fixes = {"degenerate_triangles_dropped": degen, "duplicate_triangles_dropped": dup,
             "unreferenced_vertices_dropped": unused, "triangles_flipped_for_consistency": flipped,
             "flipped_all_for_outward_normals": outward_flip}
    log("source %s:%s  %d vertices, %d triangles, %d edges, Euler characteristic %d, %d boundary "
        "loop(s) of %s edges, manifold, %s; fixes %s"
        % (tar, member, t["vertices"], t["triangles"], t["edges"], t["euler_characteristic"],
           t["boundary_loops"], t["boundary_loop_lengths"],
           "consistently oriented" if before["consistently_oriented"] else "NOT consistently oriented",
           fixes))
    source = {"file": tar + ":" + member, "vertices": t["vertices"], "triangles": t["triangles"],
              "edges": t["edges"], "euler_characteristic": t["euler_characteristic"],
              "boundary_loop_lengths": t["boundary_loop_lengths"], "fixes": fixes}
    transform = {"x_new": "(x - centre) * scale", "centre": [float(c) for c in centre],
                 "scale": scale, "rotation": "none (source axes kept)"}
    return m, source, transform


def build_cgal_disk(member, p):
    m, source, transform = cgal_disk(member)
    prov = {"source": source, "transform": transform}
    if "h" in p:
        # coarser version: gmsh remesh of the (transformed) surface at uniform size h
        X, T = gmsh_mesh(2, read_geo("remesh_surface.geo"), {"h": p["h"]}, surface=(m.X, m.T))
        m = mk.TriMesh(X, T)
        m.drop_unused_nodes()
        m.orient_consistently()
        m.orient_outward()
        m.check_disk("%s remeshed with h = %g" % (member, p["h"]))
        prov["remesh"] = {"h": p["h"], "script": "meshes/geo/remesh_surface.geo"}
    else:
        prov["remesh"] = "none: the source triangles as they are"
    (loop,) = m.boundary_loops()
    m.add_edge_set(1, "boundary", loop)
    return m, {}, prov


def build_lionhead(p):
    return build_cgal_disk("data/meshes/lion-head.off", p)


def build_nefertiti(p):
    return build_cgal_disk("data/meshes/nefertiti.off", p)


BUILDERS = {"box": build_box, "cylinder": build_cylinder, "cube": build_cube, "hexcube": build_hexcube, "armadillo": build_armadillo,
            "bunny": build_bunny, "octopus": build_octopus, "triceratops": build_triceratops,
            "hand": build_hand, "camel": build_camel, "bear": build_bear, "bull": build_bull, "homer": build_homer,
            "cloth": build_cloth, "cook": build_cook, "beam": build_beam,
            "cook_slab": build_cook_slab, "cook_slab_full": build_cook_slab_full, "cook_hex": build_cook_hex,
            "tube": build_tube, "tube_hex": build_tube_hex, "shell_hex": build_shell_hex,
            "tube_curved": build_tube_curved, "shell_curved": build_shell_curved,
            "disk": build_disk,
            "lionhead": build_lionhead, "nefertiti": build_nefertiti, "shell": build_shell}


def build(name, size, outdir):
    size = resolve(name, size)
    params = CATALOG[name][size]
    stem = os.path.join(outdir, "%s_%s" % (name, size))
    t0 = time.time()
    m, extra, prov = BUILDERS[name](params)
    s = m.stats()
    cells = CELL_KEY[kind(name, size)]
    if s["flipped_on_input"]:
        log("note: %d %s were %s as generated and got two nodes swapped"
            % (s["flipped_on_input"], cells,
               "negatively oriented" if cells == "tets" else "oriented against the others or outward/up"))
    for suffix, writer in extra.items():
        writer(stem + suffix)
    m.write_msh22(stem + ".msh")
    s["provenance"] = prov
    expected = params.get(cells)
    if expected is not None and expected != s[cells]:
        log("warning: %s/%s has %d %s, the catalog expects %d (different gmsh version?)"
            % (name, size, s[cells], cells, expected))
    with open(stem + ".json", "w") as f:
        json.dump(s, f, indent=1, sort_keys=True)
        f.write("\n")
    log(json.dumps({k: v for k, v in s.items() if k != "provenance"}, sort_keys=True))
    log("%s/%s: %d %s, %d vertices in %.1f s" % (name, size, s[cells], cells, s["vertices"], time.time() - t0))
    return s


def main(argv):
    if len(argv) == 4 and argv[0] == "build":
        build(argv[1], argv[2], argv[3])
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
