#!/usr/bin/python3
"""Builds the aries meshes. Called by meshes/generate.sh (which owns the cache); usable directly:

    build.py list                      catalog: names, sizes, parameters, expected tet counts
    build.py resolve NAME SIZE         canonical size name (aliases such as cube/paper -> default)
    build.py build NAME SIZE OUTDIR    writes OUTDIR/NAME_SIZE.msh (+ NAME_SIZE.fibers for the octopus)
                                       and OUTDIR/NAME_SIZE.json (statistics); log on stderr

All coordinates are z-up. Every tet is positively oriented and carries a physical volume. Outputs are
deterministic: gmsh runs single-threaded in a fixed sandbox with ASLR off (see GMSH_SANDBOX), and
all post-processing is plain numpy in a fixed order.
"""

import fcntl
import hashlib
import json
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

GEO = os.path.join(os.path.dirname(HERE), "geo")
GMSH = "/usr/bin/gmsh"  # fixed path: part of the reproducible argv (see GMSH_SANDBOX)
STEP_TIMEOUT = 600  # seconds, per external program run (generate.sh also bounds the whole build)

# Debian's CGAL data (package libcgal-demo). The same tarball is reachable from both doc dirs.
CGAL_DATA = [
    os.environ.get("ARIES_CGAL_DATA", ""),
    "/usr/share/doc/libcgal-dev/data.tar.gz",
    "/usr/share/doc/libcgal-demo/data.tar.gz",
]

# --------------------------------------------------------------------------------------------------
# Catalog. 'tets' is the count this generator produces with Debian 12's gmsh 4.8.4 (it is
# deterministic); a different count only warns (another gmsh version meshes differently).
# 'alias' maps a size name to another entry of the same mesh.

CATALOG = {
    "cylinder": {
        "test": {"h": 0.17, "tets": 1770},
        "default": {"h": 0.076, "tets": 17782},
        "paper": {"alias": "default"},
    },
    "cube": {
        "test": {"n": 6, "tets": 6 * 6 ** 3},
        "default": {"n": 18, "tets": 6 * 18 ** 3},
        "paper": {"alias": "default"},
    },
    "armadillo": {
        "test": {"h": 0.07, "tets": 3816},
        "default": {"h": 0.0315, "tets": 34320},
        "paper": {"alias": "default"},
    },
    "bunny": {
        "test": {"h": 0.066, "tets": 3513},
        "default": {"h": 0.0289, "tets": 35010},
        "paper": {"h": 0.0107, "tets": 639254},
    },
    "octopus": {
        "test": {"hmax": 0.4, "ncurv": 5, "tets": 4030},
        "default": {"hmax": 0.106, "ncurv": 27, "tets": 314819},
        "paper": {"alias": "default"},
    },
}

PAPER = {  # Table 1 of the paper, for the listing
    "cylinder": "17,840",
    "cube": "34,992 (pull) / 54,985 (compress)",
    "armadillo": "34,992",
    "bunny": "637,584",
    "octopus": "308,200",
}


def log(*a):
    print(*a, file=sys.stderr, flush=True)


def resolve(name, size):
    if name not in CATALOG:
        raise SystemExit("unknown mesh '%s' (known: %s)" % (name, ", ".join(CATALOG)))
    sizes = CATALOG[name]
    if size not in sizes:
        raise SystemExit("mesh '%s' has no size '%s' (sizes: %s); sizes are fixed presets so that "
                         "generation stays bounded in time and memory" % (name, size, ", ".join(sizes)))
    return sizes[size].get("alias", size)


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


def gmsh_volume(geo_text, setnumbers, surface=None):
    """gmsh -3 on a .geo script (after merging the triangle surface (V, F), if given); returns the
    (X, T) of its tets. Runs in the fixed sandbox (see above)."""
    with open(GMSH_SANDBOX + ".lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        shutil.rmtree(GMSH_SANDBOX, ignore_errors=True)
        os.mkdir(GMSH_SANDBOX)
        try:
            with open(os.path.join(GMSH_SANDBOX, "model.geo"), "w") as f:
                f.write(geo_text)
            cmd = [GMSH, "-3", "-nt", "1", "-format", "msh22", "-o", "out.msh"]
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
            return mk.read_msh22_tets(os.path.join(GMSH_SANDBOX, "out.msh"))
        finally:
            shutil.rmtree(GMSH_SANDBOX, ignore_errors=True)


def read_geo(name):
    with open(os.path.join(GEO, name)) as f:
        return f.read()


# sha256 of the source surfaces in Debian 12's libcgal-demo 5.5.1-2 (a different file only warns)
SOURCE_SHA256 = {
    "data/meshes/armadillo.off": "6f7f3ca1abc506569466b72f2f59d49493a284e7376d7a7e23c08115ec8cec4e",
    "data/meshes/bunny00.off": "ab651cb04955c161efaeb079035a1e5e1f0e0d1f816a2df67beaea68f393ff2b",
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


def build_cube(p):
    """Unit cube, n^3 grid cells, each split into the 6 Freudenthal (Kuhn) tets around the main
    diagonal: conforming, all tets congruent, 6 n^3 tets (n = 18 gives the paper's 34,992)."""
    n = p["n"]
    g = np.linspace(0.0, 1.0, n + 1)
    zz, yy, xx = np.meshgrid(g, g, g, indexing="ij")  # node id = i + (n+1) (j + (n+1) k)
    X = np.c_[xx.ravel(), yy.ravel(), zz.ravel()]
    N = n + 1
    k, j, i = np.meshgrid(np.arange(n), np.arange(n), np.arange(n), indexing="ij")
    base = (i + N * (j + N * k)).ravel()
    step = {0: 1, 1: N, 2: N * N}
    tets = []
    for perm, even in (([0, 1, 2], True), ([0, 2, 1], False), ([1, 0, 2], False),
                       ([1, 2, 0], True), ([2, 0, 1], True), ([2, 1, 0], False)):
        a = base
        b = a + step[perm[0]]
        c = b + step[perm[1]]
        d = c + step[perm[2]]
        # the path a-b-c-d along edges e_p0, e_p1, e_p2 has orientation sign(perm)
        tets.append(np.stack([a, b, c, d] if even else [a, b, d, c], 1))
    T = np.stack(tets, 1).reshape(-1, 4)  # cell-major: the 6 tets of grid cell 0, then cell 1, ...
    m = mk.TetMesh(X, T)
    m.orient()
    F, _ = m.boundary_faces()
    P = m.X[F]
    names = ["left", "right", "front", "back", "bottom", "top"]
    for tag, name in enumerate(names, start=1):
        axis, val = (tag - 1) // 2, float((tag - 1) % 2)
        m.add_face_set(tag, name, F[(np.abs(P[:, :, axis] - val) < 1e-12).all(1)])
    return m, {}, {"source": "structured Freudenthal subdivision (meshes/tools/build.py)", "n": n}


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
    m = mk.TetMesh(*remeshed_surface_volume(V, F, p["h"]))
    m.drop_unused_nodes()
    m.orient()
    Fb, _ = m.boundary_faces()
    m.add_face_set(1, "surface", Fb)
    return m, {}, {
        "source": tar + ":data/meshes/bunny00.off",
        "transform": "rotated y-up -> z-up: (x,y,z) -> (x,-z,y)",
        "h": p["h"],
    }


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


BUILDERS = {"cylinder": build_cylinder, "cube": build_cube, "armadillo": build_armadillo,
            "bunny": build_bunny, "octopus": build_octopus}


def build(name, size, outdir):
    size = resolve(name, size)
    params = CATALOG[name][size]
    stem = os.path.join(outdir, "%s_%s" % (name, size))
    t0 = time.time()
    m, extra, prov = BUILDERS[name](params)
    s = m.stats()
    if s["flipped_on_input"]:
        log("note: %d tets were negatively oriented as generated and got two nodes swapped"
            % s["flipped_on_input"])
    for suffix, writer in extra.items():
        writer(stem + suffix)
    m.write_msh22(stem + ".msh")
    s["provenance"] = prov
    expected = params.get("tets")
    if expected is not None and expected != s["tets"]:
        log("warning: %s/%s has %d tets, the catalog expects %d (different gmsh version?)"
            % (name, size, s["tets"], expected))
    with open(stem + ".json", "w") as f:
        json.dump(s, f, indent=1, sort_keys=True)
        f.write("\n")
    log(json.dumps({k: v for k, v in s.items() if k != "provenance"}, sort_keys=True))
    log("%s/%s: %d tets, %d vertices in %.1f s" % (name, size, s["tets"], s["vertices"], time.time() - t0))
    return s


def listing():
    print("%-10s %-8s %-8s %-22s %s" % ("name", "size", "tets", "parameters", "paper (Table 1)"))
    for name, sizes in CATALOG.items():
        paper_size = resolve(name, "paper")
        for size, p in sizes.items():
            if "alias" in p:
                print("%-10s %-8s %-8s %-22s" % (name, size, "", "= " + p["alias"]))
                continue
            par = " ".join("%s=%g" % (k, v) for k, v in p.items() if k != "tets")
            print("%-10s %-8s %-8d %-22s %s" % (name, size, p["tets"], par,
                                              PAPER[name] if size == paper_size else ""))


def main(argv):
    if len(argv) >= 1 and argv[0] == "list":
        listing()
    elif len(argv) == 3 and argv[0] == "resolve":
        print(resolve(argv[1], argv[2]))
    elif len(argv) == 4 and argv[0] == "build":
        build(argv[1], argv[2], argv[3])
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
