"""End-to-end cases: the command line (-help, -version, misspelled options, shipped options files), the output (XDMF
read by meshio and ParaView, output fields, output times) and the post-processing scripts."""
import glob
import json
import os
import re
import subprocess
import sys

import h5py
import numpy as np

from harness import aries_cmd, fail, mpi_env, step_file
from .common import ARGS, CONVERGED, mesh, out_base, read_state, run, stats


def case_options_file(name):
    """A shipped options file runs with -options_left clean (no unused option) on the test-size mesh of its scene, 2
    steps: both converge (the kim_aa scenes: the baseline fails cleanly, exit 3, with a failure reason in its stats) and
    the positions written are finite."""
    path = os.path.join(ARGS.root, "options", name + ".yml")
    text = open(path).read()
    m = re.search(r"^dm_plex_filename:\s*meshes/cache/(\w+?)_(default|paper|fig15)\.msh", text, re.M)
    if not m:
        fail("%s does not name a meshes/cache mesh" % path)
    msh = mesh(m.group(1))
    extra = ["-fiber_file", msh[:-4] + ".fibers"] if "fiber_file" in text else []
    if "target_file" in text:
        extra += ["-target_file", msh[:-4] + ".targets"]
    if "dm_plex_gmsh_spacedim" in text:
        extra += ["-dm_plex_gmsh_spacedim", "3"]
    tag = "options_%s_np%d" % (name, ARGS.ranks)
    expect = 3 if "kim_aa" in name else 0
    log, _ = run(["-options_file", path, "-dm_plex_filename", msh] + extra +
                 ["-steps", "2", "-output", out_base(tag), "-stats", out_base(tag) + ".csv", "-options_left",
                  "-strict"], expect_code=expect, tag=tag)
    if "were not used" in log or "Option left" in log:
        fail("unused options reported:\n" + log[-2000:])
    reasons = [r["reason"] for r in stats(out_base(tag) + ".csv")]
    print("%s: step reasons %s" % (name, reasons))
    if expect == 0 and (len(reasons) != 2 or any(r not in CONVERGED for r in reasons)):
        fail("%s: expected 2 converged steps, got %s" % (name, reasons))
    if expect != 0 and (not reasons or reasons[-1] in CONVERGED):
        fail("%s: the failing baseline's last step reports %s, expected a failure reason" % (name, reasons))
    _, _, x, _ = read_state(out_base(tag))
    if not np.all(np.isfinite(x)):
        fail("%s: the written positions are not finite" % name)


def case_unused_option_warning():
    """A misspelled option (-enrgy) does not pass silently: the run goes on with the defaults and stderr carries exactly
    one line, a warning naming the option and the declared one it is nearest to (-energy); a declared option that this
    configuration does not read (-predictor_start in a static run) is named as such, not suggested to itself; -strict
    turns the warning into an error (exit 1)."""
    tag = "unused_np%d" % ARGS.ranks
    cmd = aries_cmd(ARGS.aries, ARGS.ranks, ["-dm_plex_filename", mesh("bunny"), "-enrgy", "iarap",
                                             "-predictor_start", "0", "-steps", "1", "-output", out_base(tag)])
    print("$ " + " ".join(cmd), flush=True)
    p = subprocess.run(cmd, capture_output=True, text=True, env=mpi_env(), cwd=ARGS.work, timeout=300)
    err = [l for l in p.stderr.splitlines() if l.strip()]
    print("exit %d; stderr:\n%s" % (p.returncode, "\n".join(err)))
    if p.returncode != 0:
        fail("exit code %d, expected 0 (a warning, not an error)" % p.returncode)
    if len(err) != 1 or not err[0].startswith("aries: warning: ") or "-enrgy" not in err[0]:
        fail("expected one 'aries: warning:' line on stderr naming -enrgy")
    for expected in ("-enrgy (did you mean -energy?)", "-predictor_start (not read by this configuration)"):
        if expected not in err[0]:
            fail("the warning line does not say '%s'" % expected)
    if not os.path.exists(out_base(tag) + ".xmf"):
        fail("the run did not write its output")
    run(["-dm_plex_filename", mesh("bunny"), "-enrgy", "iarap", "-steps", "1", "-strict"], expect_code=1,
        tag=tag + "_strict")


# Options aries queries but does not own: PETSc's -help, the gmsh reader's vertex labels, which aries switches on
# (lib/mesh/mesh.cpp: the boundary sets need them) unless the user sets the PETSc option, and its high-order coordinates,
# which aries switches off (lib/mesh/mesh_facets.cpp: a second-order mesh is read as its corners; docs/options.md).
NOT_ARIES_OPTIONS = {"-help", "-dm_plex_gmsh_mark_vertices", "-dm_plex_gmsh_highorder"}


def documented_options():
    """Option names of the option tables of docs/options.md (generated from the declarations, ctest docs.options),
    the energy names and the output fields."""
    with open(os.path.join(ARGS.root, "docs", "options.md")) as fh:
        md = fh.read()
    opts, energies, fields = set(), set(), set()
    for block in re.findall(r"<!-- options:(\w+) -->\n(.*?)<!-- /options -->", md, re.S):
        key, body = block
        if key == "matpoint":  # aries-matpoint's own options (its -help: ctest/check_matpoint.py)
            continue
        for row in re.findall(r"^\| `([^`]+)` \|", body, re.M):
            if key == "energies":
                energies.add(row)
            elif key == "output_fields":
                fields.add(row)
            else:
                opts |= set(re.findall(r"(?<![A-Za-z0-9_])(-[A-Za-z][A-Za-z0-9_<>]*)", row))
    return opts, energies, fields


def case_help():
    """`aries -help` lists every option of docs/options.md's tables with its default and meaning, every energy and
    output field (exit 0), from the same declarations; every option the code reads outside the declared readers
    (PETSc's own, queried by name) is documented; with a mesh, -help sets the run up so PETSc lists the SNES, line
    search, KSP, PC and DM options too, and nothing is computed or written."""
    log, _ = run(["-help"], tag="help")
    opts, energies, fields = documented_options()
    if len(opts) < 60 or len(energies) < 10 or len(fields) < 10:
        fail("docs/options.md parsed to %d options, %d energies, %d fields" % (len(opts), len(energies), len(fields)))
    usage = set(re.findall(r"^  (\S+)", log, re.M))
    missing = sorted(o for o in opts if o not in log)
    missing += sorted(e for e in energies | fields if e not in usage)
    if missing:
        fail("-help does not list: %s" % ", ".join(missing))
    # The energy section is printed from the registry (lib/energies/catalog/): it and the docs' table agree.
    section = log.split("Energies (-energy NAME", 1)[-1]
    registry = set(re.findall(r"^  (\S+) \[", section.split("Output fields", 1)[0], re.M))
    if len(registry) < 10 or registry != energies:
        fail("the registry's energies (-help) and docs/options.md's energy table differ: only in the registry %s, only "
             "in the docs %s" % (sorted(registry - energies), sorted(energies - registry)))
    with open(os.path.join(ARGS.root, "docs", "energies.md")) as fh:
        conventions = set(re.findall(r"^\| `([a-z0-9_]+)` \|", fh.read(), re.M))
    if registry != conventions:
        fail("the registry's energies and docs/energies.md's table differ: %s vs %s"
             % (sorted(registry - conventions), sorted(conventions - registry)))
    if "-newton_tol X [1e-4 (static), 1e-2 (beuler); > 0]" not in log:
        fail("-help does not show -newton_tol with its per-integrator default")
    # Every read goes through a declaration (core::get, which refuses an undeclared option) except PETSc's own
    # options that aries queries by name: those must be documented in the prose.
    src = ""
    for f in glob.glob(os.path.join(ARGS.root, "lib", "**", "*.[ch]pp"), recursive=True) + \
            glob.glob(os.path.join(ARGS.root, "app", "*.cpp")):
        with open(f) as fh:
            src += fh.read()
    raw = set(re.findall(r'option(?:String|Real|Int|Bool|RealList|WordList)\(\s*[^,()]*,\s*"(-[A-Za-z0-9_]+)"', src))
    raw |= set(re.findall(r'PetscOptions(?:HasName|GetString|GetReal|GetInt|GetBool)\(\s*[^,]*,\s*[^,]*,\s*'
                          r'"(-[A-Za-z0-9_]+)"', src))
    declared_reads = len(re.findall(r"core::get(?:Choice)?\(", src))
    if declared_reads < 60:
        fail("the source scan found only %d declared reads" % declared_reads)
    with open(os.path.join(ARGS.root, "docs", "options.md")) as fh:
        anywhere = set(re.findall(r"`(-[A-Za-z][A-Za-z0-9_]*)", fh.read()))
    undocumented = sorted(raw - opts - anywhere - NOT_ARIES_OPTIONS)
    if undocumented:
        fail("options read by name but not in docs/options.md: %s" % ", ".join(undocumented))
    print("-help lists %d options, %d energies, %d output fields; %d declared reads, %d PETSc options queried by "
          "name, all documented" % (len(opts), len(energies), len(fields), declared_reads, len(raw)))
    tag = "help_mesh"
    log, _ = run(["-dm_plex_filename", mesh("bunny"), "-steps", "1", "-output", out_base(tag), "-help"], tag=tag)
    for petsc in ("-snes_type", "-snes_linesearch_type", "-ksp_type", "-ksp_rtol", "-pc_type", "-dm_plex_gmsh"):
        if not re.search(r"^\s*%s" % re.escape(petsc), log, re.M):
            fail("-help with a mesh does not list PETSc's %s options" % petsc)
    if os.path.exists(out_base(tag) + ".xmf") or os.path.exists(out_base(tag) + ".h5"):
        fail("-help wrote output")
    # PETSc's viewers work and are not reported as unused: -dm_view prints the distributed mesh, -snes_view the solver.
    log, _ = run(["-dm_plex_filename", mesh("bunny"), "-steps", "1", "-dm_view", "-snes_view"], tag="viewers")
    if "DM Object: aries_mesh" not in log or "SNES Object" not in log or "unused" in log:
        fail("-dm_view / -snes_view did not print the mesh and the solver, or were reported unused")


def case_scripts():
    """The post-processing scripts on a real run: render_png.py draws the stress, J and alpha fields with a colour bar
    and a caption carrying each field's actual range (and stops with one error line naming the fields present when
    asked for one that was not written); plot_stats.py charts the stats CSV."""
    tag = "scripts"
    run(["-options_file", os.path.join(ARGS.root, "options", "bunny_inside_out.yml"), "-dm_plex_filename", mesh("bunny"),
         "-steps", "2", "-output", out_base(tag), "-output_every", "1", "-stats", out_base(tag) + ".csv",
         "-output_fields", "alpha,J,von_mises,cauchy_stress"], tag=tag)
    py = "/usr/bin/python3"
    for field, expect in (("stress", r"von Mises stress: \S+ \.\. \S+"), ("J", r"J = det F: \S+ \.\. \S+"),
                          ("alpha", r"alpha of the adjacent cell .*, rest 64, \d+ of \d+ cells at alpha = 0"), ("cauchy_stress", r"\|cauchy_stress\|")):
        png = out_base(tag) + "_%s.png" % field
        p = subprocess.run([py, os.path.join(ARGS.root, "scripts", "render_png.py"), out_base(tag), png, "--field", field,
                            "--step", "0" if field == "alpha" else "2"], capture_output=True, text=True)
        print(p.stdout.strip() + p.stderr.strip())
        if p.returncode != 0 or not re.search(expect, p.stdout) or os.path.getsize(png) < 10000:
            fail("render_png.py --field %s: exit %d, caption not /%s/ or no image" % (field, p.returncode, expect))
    start = subprocess.run([py, os.path.join(ARGS.root, "scripts", "render_png.py"), out_base(tag),
                            out_base(tag) + "_start.png", "--field", "J", "--step", "0"], capture_output=True, text=True)
    m = re.search(r"\((\d+) inverted cells\)", start.stdout)
    if not m or int(m.group(1)) == 0:
        fail("the caption of the inside-out start should count its inverted cells: %s" % start.stdout.strip())
    p = subprocess.run([py, os.path.join(ARGS.root, "scripts", "render_png.py"), out_base(tag), out_base(tag) + "_x.png",
                        "--field", "pk1_stress"], capture_output=True, text=True)
    err = [l for l in p.stderr.splitlines() if l.strip()]
    print("\n".join(err))
    if p.returncode == 0 or len(err) != 1 or not err[0].startswith("render_png: error: field 'pk1_stress'") \
            or "von_mises" not in err[0]:
        fail("render_png.py with a field not written should stop with one error line naming the fields present")
    png = out_base(tag) + "_stats.png"
    p = subprocess.run([py, os.path.join(ARGS.root, "scripts", "plot_stats.py"), out_base(tag) + ".csv", png],
                       capture_output=True, text=True)
    print(p.stdout.strip() + p.stderr.strip())
    if p.returncode != 0 or os.path.getsize(png) < 10000:
        fail("plot_stats.py failed (exit %d)" % p.returncode)


def case_paraview():
    """ParaView as a client: pvpython (headless under xvfb-run) opens the XDMF of a compressed cylinder, warps the rest
    geometry by `displacement` with scale 1 and renders the von Mises stress (scripts/paraview_screenshot.py); the
    warped geometry must match the positions aries wrote. The same for quadratic tetrahedra (-element p2: ParaView
    reads the Tetrahedron_10 topology). Skipped (exit 77, shown as skipped by ctest) where pvpython or
    xvfb-run is not installed."""
    import shutil
    if not shutil.which("pvpython") or not shutil.which("xvfb-run"):
        print("SKIPPED: pvpython or xvfb-run is not installed (Debian: apt-get install paraview python3-paraview xvfb)")
        sys.exit(77)
    for tag, extra in (("paraview", []), ("paraview_p2", ["-element", "p2"])):
        run(["-options_file", os.path.join(ARGS.root, "options", "cylinder_compress.yml"), "-dm_plex_filename",
             mesh("cylinder"), "-output", out_base(tag), "-output_fields", "von_mises,J"] + extra, tag=tag)
        png = out_base(tag) + ".png"
        cmd = ["xvfb-run", "-a", "pvpython", "--force-offscreen-rendering",
               os.path.join(ARGS.root, "scripts", "paraview_screenshot.py"), out_base(tag) + ".xmf", png, "--field",
               "von_mises", "--check-positions", out_base(tag)]
        print("$ " + " ".join(cmd), flush=True)
        # The virtual X server sometimes is not ready when the render window opens (seen under ctest -j2: SIGABRT in
        # vtkXOpenGLRenderWindow::CreateAWindow before anything is read); that start-up failure, and only it, is
        # retried.
        for attempt in range(3):
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
            if not (p.returncode != 0 and "CreateAWindow" in p.stderr):
                break
            print("attempt %d: the X server was not ready (SIGABRT in CreateAWindow); retrying" % (attempt + 1))
        print(p.stdout.strip())
        print(p.stderr.strip()[-2000:])
        m = re.search(r"warped geometry vs positions: max \|diff\| ([0-9.eE+-]+)", p.stdout)
        if p.returncode != 0 or not os.path.exists(png) or os.path.getsize(png) < 20000:
            fail("%s: paraview_screenshot.py failed (exit %d) or wrote no image" % (tag, p.returncode))
        if not m or not float(m.group(1)) <= 1e-12:
            fail("%s: ParaView's warped geometry does not match the positions aries wrote" % tag)


def case_version():
    """-version prints the aries version and git commit (exit 0); the same pair is in every output .h5 file (root
    attributes aries_version / aries_commit) and in the first line of the stats CSV."""
    log, _ = run(["-version"], tag="version")
    m = re.search(r"^aries (\d+\.\d+\.\d+) \(git ([0-9a-f]{7,}(-dirty)?|unknown)\)$", log, re.M)
    if not m:
        fail("-version did not print 'aries X.Y.Z (git COMMIT)'")
    version, commit = m.group(1), m.group(2)
    tag = "version_run"
    run(["-dm_plex_filename", mesh("bunny"), "-steps", "1", "-output", out_base(tag), "-stats", out_base(tag) + ".csv"],
        tag=tag)
    with open(out_base(tag) + ".csv") as fh:
        first = fh.readline().strip()
    if first != "# aries %s (git %s)" % (version, commit):
        fail("stats header line %r does not name aries %s (git %s)" % (first, version, commit))
    for path in (out_base(tag) + ".h5", step_file(out_base(tag), 1)):
        with h5py.File(path, "r") as h:
            got = (h.attrs["aries_version"].decode(), h.attrs["aries_commit"].decode())
        if got != (version, commit):
            fail("%s carries %s, expected %s" % (path, got, (version, commit)))
    print("aries %s (git %s) in -version, the stats header and the output files" % (version, commit))


def case_output_times():
    """Output times are start + k dt, not a running sum: three steps of dt = 0.1 are at 0.1, 0.2, 0.3 exactly (k * 0.1
    in double, 0.30000000000000004 for k = 3) in the step files, and the XDMF index reads 0.1, 0.2, 0.3."""
    tag = "times"
    run(["-dm_plex_filename", mesh("bunny"), "-steps", "3", "-dt", "0.1", "-integrator", "beuler",
         "-output", out_base(tag)], tag=tag)
    with open(out_base(tag) + ".xmf") as fh:
        shown = re.findall(r'<Time Value="([^"]*)"', fh.read())
    print("XDMF times:", shown)
    if shown != ["0", "0.1", "0.2", "0.3"]:
        fail("XDMF times %s, expected 0, 0.1, 0.2, 0.3" % shown)
    for k in (1, 2, 3):
        with h5py.File(step_file(out_base(tag), k), "r") as h:
            t = float(h.attrs["time"])
        if t != k * 0.1:
            fail("step %d is at t = %.17g, expected %.17g (k dt)" % (k, t, k * 0.1))


def case_meshio_xdmf():
    """The XDMF output read by a third-party client (meshio's TimeSeriesReader): one mesh, the rest geometry and
    topology of the input .msh file (read by meshio too), then per step a displacement whose sum with the rest
    geometry is the positions aries computed, the cell fields (with -output_fields all: the stress and strain fields
    of the inside-out bunny, checked cell by cell against each other and against F), and the step times k dt."""
    import meshio
    tag = "meshio_np%d" % ARGS.ranks
    run(["-options_file", os.path.join(ARGS.root, "options", "bunny_inside_out.yml"), "-dm_plex_filename",
         mesh("bunny"), "-steps", "3", "-output", out_base(tag), "-output_every", "1", "-stats", out_base(tag) + ".csv",
         "-output_fields", "all"], tag=tag)
    msh = meshio.read(mesh("bunny"))
    msh_tets = [c.data for c in msh.cells if c.type == "tetra"][0]
    with meshio.xdmf.TimeSeriesReader(out_base(tag) + ".xmf") as r:
        points, cells = r.read_points_cells()
        if len(cells) != 1 or cells[0].type != "tetra":
            fail("expected one tetra cell block, got %s" % [c.type for c in cells])
        if points.shape != msh.points.shape or np.abs(points - msh.points).max() > 1e-12:
            fail("the XDMF geometry is not the rest shape of the input mesh")
        if not (np.sort(cells[0].data, 1) == np.sort(msh_tets, 1)).all():
            fail("the XDMF topology is not the input mesh's tetrahedra")
        if r.num_steps != 4:
            fail("expected 4 time steps (initial + 3), got %d" % r.num_steps)
        worst = 0.0
        for k in range(r.num_steps):
            t, point_data, cell_data = r.read_data(k)
            if abs(t - k * 0.01) > 1e-15:
                fail("step %d at t = %r, expected %g" % (k, t, k * 0.01))
            for name, comps in (("alpha", 1), ("energy_density", 1), ("J", 1), ("von_mises", 1), ("cauchy_stress", 9),
                                ("pk1_stress", 9), ("green_strain", 9), ("deformation_gradient", 9),
                                ("principal_stretches", 3)):
                if name not in cell_data or cell_data[name][0].shape[0] != len(msh_tets) or \
                        (cell_data[name][0].reshape(len(msh_tets), -1).shape[1] != comps):
                    fail("cell field %s missing or of the wrong shape at step %d" % (name, k))
            # The stress and strain fields of an inside-out body, checked against each other cell by cell:
            # J = det F, E = (F^T F - I)/2, sigma = P F^T / J (where J != 0), von Mises of sigma, and the principal
            # stretches' product = J (signed for inverted cells).
            F = cell_data["deformation_gradient"][0].reshape(-1, 3, 3)
            P = cell_data["pk1_stress"][0].reshape(-1, 3, 3)
            J = cell_data["J"][0].reshape(-1)
            if np.abs(np.linalg.det(F) - J).max() > 1e-12 * max(1.0, np.abs(J).max()):
                fail("step %d: J is not det F" % k)
            E = cell_data["green_strain"][0].reshape(-1, 3, 3)
            if np.abs(E - 0.5 * (np.einsum("kji,kjl->kil", F, F) - np.eye(3))).max() > 1e-12 * max(1.0, np.abs(E).max()):
                fail("step %d: green_strain is not (F^T F - I)/2" % k)
            ok = np.abs(J) > 1e-6
            sig = cell_data["cauchy_stress"][0].reshape(-1, 3, 3)
            ref = np.einsum("kij,klj->kil", P, F) / J[:, None, None]
            if np.abs(sig[ok] - ref[ok]).max() > 1e-9 * np.abs(ref[ok]).max():
                fail("step %d: cauchy_stress is not P F^T / J" % k)
            dev = sig - np.trace(sig, axis1=1, axis2=2)[:, None, None] * np.eye(3) / 3.0
            vm = np.sqrt(1.5 * np.einsum("kij,kij->k", dev, dev))
            if np.abs(vm[ok] - cell_data["von_mises"][0].reshape(-1)[ok]).max() > 1e-9 * vm[ok].max():
                fail("step %d: von_mises does not match cauchy_stress" % k)
            lam = cell_data["principal_stretches"][0].reshape(-1, 3)
            if np.abs(lam.prod(1) - J).max() > 1e-10 * max(1.0, np.abs(J).max()):
                fail("step %d: the principal stretches' product is not J" % k)
            if k == 0 and not (J < 0).sum() > len(J) // 2:
                fail("the inside-out start should have most cells inverted (J < 0): %d of %d" % ((J < 0).sum(), len(J)))
            with h5py.File(step_file(out_base(tag), k), "r") as h:
                x = h["/positions"][:]
            worst = max(worst, np.abs(points + point_data["displacement"] - x).max())
    L = np.linalg.norm(points.max(0) - points.min(0))
    print("meshio: rest geometry and topology match the .msh; max |rest + displacement - positions| / L = %.2e" % (worst / L))
    if not worst <= 1e-12 * L:
        fail("rest + displacement differs from the positions by %.3e" % worst)


def case_output_fields():
    """The mechanics output fields (-output_fields) against the material point tool: a cube (nu = 0) with its bottom
    face pinned and its top face moved up 20% is a uniform uniaxial stretch F = diag(1, 1, 1.2), so every cell's PK1
    stress is aries-matpoint's P at that F, its Cauchy stress P F^T / J, von Mises |sigma_zz|, J 1.2, Green-Lagrange
    diag(0, 0, 0.22), principal stretches (1.2, 1, 1); the reactions on the top face sum to P_zz times its area (1)
    and those on the bottom to minus that; the marker is the box index. All read through meshio's XDMF reader. Then a
    free fall under gravity (backward Euler, no support): every vertex's velocity is k dt g after k steps."""
    import meshio
    s = 1.2
    tag = "fields_static_np%d" % ARGS.ranks
    run(["-dm_plex_filename", mesh("cube"), "-energy", "iarap", "-E", "1e4", "-nu", "0", "-integrator", "static",
         "-steps", "2", "-bc_box", "-1,2,-1,2,-1,0.01,-1,2,-1,2,0.99,2", "-bc_box_2_translate", "0,0,%g" % (s - 1),
         "-output", out_base(tag), "-output_fields", "all"], tag=tag)
    mp = subprocess.run([os.path.join(os.path.dirname(ARGS.aries), "aries-matpoint"), "-energy", "iarap", "-E", "1e4",
                         "-nu", "0", "-F", "1,0,0,0,1,0,0,0,%r" % s, "-json"], capture_output=True, text=True, check=True)
    P = np.array(json.loads(mp.stdout)["pk1"]).reshape(3, 3)
    F = np.diag([1.0, 1.0, s])
    sigma = P @ F.T / s
    with meshio.xdmf.TimeSeriesReader(out_base(tag) + ".xmf") as r:
        points, cells = r.read_points_cells()
        t, point_data, cell_data = r.read_data(r.num_steps - 1)
    c = {k: v[0] for k, v in cell_data.items()}
    expected = {"pk1_stress": P.ravel(), "cauchy_stress": sigma.ravel(), "deformation_gradient": F.ravel(),
                "green_strain": (0.5 * (F.T @ F - np.eye(3))).ravel(), "principal_stretches": np.array([s, 1.0, 1.0]),
                "J": np.array([s]), "von_mises": np.array([abs(sigma[2, 2])]), "region": np.array([0.0])}
    scale = np.abs(P).max()
    for name, want in sorted(expected.items()):
        if name not in c:
            fail("cell field %s missing (fields: %s)" % (name, sorted(c)))
        got = c[name].reshape(len(c[name]), -1)
        tol = 1e-8 * (scale if name in ("pk1_stress", "cauchy_stress", "von_mises") else 1.0)
        err = np.abs(got - want[None, :]).max()
        print("%-21s max |cell - expected| = %.2e (tolerance %.1e)" % (name, err, tol))
        if not err <= tol:
            fail("%s differs from the uniform uniaxial stretch by %.3e" % (name, err))
    marker, reaction = point_data["marker"].ravel(), point_data["reaction"]
    top, bottom = reaction[marker == 2].sum(0), reaction[marker == 1].sum(0)
    print("reaction: top %s, bottom %s; P_zz x area = %.6g" % (top, bottom, P[2, 2]))
    if not (np.abs(points[marker == 2, 2] - 1.0).max() < 1e-12 and np.abs(points[marker == 1, 2]).max() < 1e-12):
        fail("the marker does not match the pinned boxes")
    if np.abs(reaction[marker == 0]).max() != 0.0:
        fail("a free vertex has a nonzero reaction")
    if not (abs(top[2] - P[2, 2]) <= 1e-6 * scale and abs(bottom[2] + P[2, 2]) <= 1e-6 * scale
            and np.abs(top[:2]).max() <= 1e-6 * scale):
        fail("reactions %s / %s, expected +-%g along z" % (top, bottom, P[2, 2]))
    if "velocity" in point_data:
        fail("a static run wrote a velocity field")
    # free fall: velocities
    tag = "fields_fall_np%d" % ARGS.ranks
    run(["-dm_plex_filename", mesh("cube"), "-energy", "iarap", "-E", "1e4", "-nu", "0.3", "-integrator", "beuler",
         "-dt", "0.01", "-steps", "3", "-gravity", "0,0,-9.81", "-output", out_base(tag), "-output_fields",
         "velocity,J"], tag=tag)
    with h5py.File(step_file(out_base(tag), 3), "r") as h:
        v = h["/vertex/velocity"][:]
        if sorted(h["/cell"].keys()) != ["J"]:
            fail("-output_fields velocity,J wrote cell fields %s" % sorted(h["/cell"].keys()))
    err = np.abs(v - np.array([0.0, 0.0, -9.81 * 0.03])[None, :]).max()
    print("free fall: max |v - 3 dt g| = %.2e" % err)
    if not err <= 1e-10:
        fail("velocity after 3 steps of free fall off by %.3e" % err)


CASES = {
    "unused_option_warning": case_unused_option_warning,
    "help": case_help,
    "scripts": case_scripts,
    "paraview": case_paraview,
    "version": case_version,
    "output_times": case_output_times,
    "meshio_xdmf": case_meshio_xdmf,
    "output_fields": case_output_fields,
}
