#!/usr/bin/env python3
"""Table 1 / Table 2 rows for the paper's scenes at the paper's sizes, beside the paper's numbers.

usage: bench/scenes.py [--table 1|2] [--steps K] [--ranks N] [--build DIR] [--out FILE.md] [--resume K] [--reuse]
                       [--options 'ARIES OPTIONS'] [--ranges A-B,...] [SCENE ...]

Runs each scene's options file (options/*.yml, meshes generated on demand) with its paper-size mesh and writes a
markdown table. Table 1 (volumetric): elements, E, nu, dt, steps, Newton/step, solves/step, PCG/step, s/step, failed
steps. Table 2 (cloth, the default cloth mesh): model, stretch, shear, bending, steps, Newton/step, solves/step,
PCG/step, s/step; it also renders the final cloth states to PNG (bench/results/images/). Paper: 20-core 3.8 GHz i9,
Eigen PCG + Jacobi. --steps K runs only the first K steps of each scene (the averages are then over those steps,
stated in the table); without it every scene runs its full length (hours on 2 cores for the largest). --resume K
checkpoints every K steps, so that a run cut short (a session's end) continues where it stopped when the same command
is given again, and so does a run stopped at --steps K short of the scene's length when given again with a larger K
(the averages are then over the steps run so far, as with --steps); a scene run to its end has its checkpoint
removed. --reuse reads a finished scene back (its work directory holds stats for every step asked for, and no
checkpoint unless the run stopped at --steps K short of the scene's length) instead of running it again; the table
names the aries build of each row read back or continued from a checkpoint (a table can so be completed scene by
scene across sessions). --options adds aries options to every scene's command line (after the scene's own; e.g.
'-predictor_acceleration false' for a row without an option's effect; give it its own --work, since a checkpoint or a
stats file in the work directory is that run's). --ranges A-B,C-D adds a table of the same averages over each range of
steps (the phases of a scene: e.g. the Fig. 13 interaction's 1-55, 56-100 and 101-200). Default output:
bench/results/table<N>.md; its header names the command, the date and the commit the runs were made at. Use
/usr/bin/python3 (Debian's).
"""
import argparse
import csv
import datetime
import json
import os
import platform
import re
import shlex
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# scene name -> (options file, extra options, mesh (name, size), paper row: elems, E, nu, dt, steps, newton, pcg, s)
SCENES = {
    "cube_ortho_compress": ("cube_ortho_compress", [], ("cube", "default"), (54985, 1e3, 0.3, 1e-2, 50, 1.9, 906.3, 0.41)),
    "cube_ortho_pull": ("cube_ortho_pull", [], ("cube", "default"), (34992, 1e3, 0.3, 1e-2, 50, 1.5, 874.7, 0.38)),
    "armadillo_scramble": ("armadillo_scramble", [], ("armadillo", "default"), (34992, 1e5, 0.0, 1e-2, 2000, 2.8, 411.3, 0.71)),
    "bunny_inside_out": ("bunny_inside_out", [], ("bunny", "paper"), (637584, 1e4, 0.0, 1e-2, 200, 26.0, 15663.6, 128.76)),
    "cylinder_compress_nu0": ("cylinder_compress", ["-nu", "0"], ("cylinder", "default"), (17840, 1e4, 0.0, 1e-2, 100, 1.3, 490.6, 0.16)),
    "cylinder_compress_nu0.3": ("cylinder_compress", ["-nu", "0.3"], ("cylinder", "default"), (17840, 1e4, 0.3, 1e-2, 100, 1.4, 644.8, 0.18)),
    "cylinder_compress_nu0.49": ("cylinder_compress", ["-nu", "0.49"], ("cylinder", "default"), (17840, 1e4, 0.49, 1e-2, 100, 1.8, 2509.4, 0.31)),
    "cylinder_pull_nu0": ("cylinder_pull", ["-nu", "0"], ("cylinder", "default"), (17840, 1e4, 0.0, 1e-2, 200, 1.6, 544.7, 0.18)),
    "cylinder_pull_nu0.3": ("cylinder_pull", ["-nu", "0.3"], ("cylinder", "default"), (17840, 1e4, 0.3, 1e-2, 200, 1.8, 775.8, 0.22)),
    "cylinder_pull_nu0.49": ("cylinder_pull", ["-nu", "0.49"], ("cylinder", "default"), (17840, 1e4, 0.49, 1e-2, 200, 3.1, 3685.7, 0.44)),
    # The paper's regime: its PCG counts point to stiffness-dominated systems (its density is not stated); density 1
    # keeps the scene and makes the dt = 1e-2 systems stiffness-dominated (cylinder compress, nu = 0.3: 22 PCG per
    # Newton system at density 1000, 251 at density 1, 323 quasistatic; the paper's row: 645).
    "cylinder_compress_nu0.3_rho1": ("cylinder_compress", ["-nu", "0.3", "-density", "1"], ("cylinder", "default"),
                                     (17840, 1e4, 0.3, 1e-2, 100, 1.4, 644.8, 0.18)),
    "armadillo_scramble_rho1": ("armadillo_scramble", ["-density", "1"], ("armadillo", "default"),
                                (34992, 1e5, 0.0, 1e-2, 2000, 2.8, 411.3, 0.71)),
    "bunny_inside_out_rho1": ("bunny_inside_out", ["-density", "1"], ("bunny", "paper"),
                              (637584, 1e4, 0.0, 1e-2, 200, 26.0, 15663.6, 128.76)),
    "octopus_iso": ("octopus_iso", [], ("octopus", "default"), (308200, 1e3, 0.0, 1e-2, 400, 3.5, 1738.9, 8.54)),
    "octopus_fiber": ("octopus_fiber", [], ("octopus", "default"), (308200, 1e3, 0.0, 1e-2, 400, 3.8, 24010.2, 53.02)),
    "octopus_stiff": ("octopus_stiff", [], ("octopus", "default"), (308200, 1e5, 0.0, 1e-2, 400, 1.0, 4980.3, 12.61)),
    # Active materials (Sec. 5.3, 6). The paper's Fig. 13 uses a 200,739-hex face; we use the tet bunny (the paper
    # row is beside ours for scale only). Static rows: the dt column is the scene's time increment. Paper values
    # from Table 1 (Fig. 13 interp: 3.3 Newton, 77,701.5 PCG, 1,026.22 s; Fig. 15(b)/(c): 25 / 67 Newton,
    # 85,179 / 269,221 PCG, 219.69 / 685.93 s, one static solve each).
    "bunny_guided": ("bunny_guided", [], ("bunny", "default"), (200739, 1e2, 0.4, 0.05, 20, 3.3, 77701.5, 1026.22)),
    "bunny_interact": ("bunny_interact", [], ("bunny", "default"), (200739, 1e2, 0.4, 1e-2, 200, 1.0, 745.9, 68.04)),
    # Fig. 13 on hexahedra as in the paper: the voxelized bunny (meshes/generate.sh bunny hex: 199,368 trilinear hexes).
    "bunny_guided_hex": ("bunny_guided", [], ("bunny", "hex"), (200739, 1e2, 0.4, 0.05, 20, 3.3, 77701.5, 1026.22)),
    "bunny_interact_hex": ("bunny_interact", [], ("bunny", "hex"), (200739, 1e2, 0.4, 1e-2, 200, 1.0, 745.9, 68.04)),
    "bunny_caricature": ("bunny_caricature", [], ("bunny", "fig15"), (292476, 1e2, 0.0, 1, 1, 25, 85179, 219.69)),
    "armadillo_caricature": ("armadillo_caricature", [], ("armadillo", "fig15"),
                             (292476, 1e2, 0.0, 1, 1, 67, 269221, 685.93)),
}

# Table 2: scene -> (options file, extra options, row label, paper row: stretch, shear, bending, steps, newton, pcg, s)
CLOTH = {
    "drop_iso": ("cloth_drop_iso", [], "isotropic drop, Eq. 49 (Lin 2022)", (40, 40, 1e-3, 1000, 1.3, 1270.2, 0.67)),
    "drop_ours": ("cloth_drop_ours", [], "isotropic drop, Eq. 51/53 ours", (40, 80, 1e-3, 1000, 1.4, 1540.0, 0.81)),
    "drop_bw": ("cloth_drop_bw", [], "isotropic drop, Eq. 45 (Kim 2020)", (40, 80, 1e-3, 1000, 1.4, 2830.0, 0.95)),
    "drop_ours_aniso": ("cloth_drop_ours", ["-fiber2", "1,1"], "anisotropic drop, ours (b = [1,1])",
                        (40, 80, 1e-3, 1000, 2.5, 3039.3, 1.31)),
    "drop_bw_aniso": ("cloth_drop_bw", ["-fiber2", "1,1"], "anisotropic drop, Kim 2020 (b = [1,1])",
                      (40, 80, 1e-3, 1000, 2.6, 5396.4, 1.73)),
    "stretch_iso": ("cloth_stretch_iso", [], "isotropic stretch, Eq. 49 (Lin 2022)", (20, 20, 1e-3, 200, 1.1, 587.3, 0.56)),
    "stretch_ours": ("cloth_stretch_ours", [], "isotropic stretch, Eq. 51/53 ours", (20, 30, 1e-3, 200, 1.6, 946.3, 0.65)),
    "stretch_bw": ("cloth_stretch_bw", [], "isotropic stretch, Eq. 45 (Kim 2020)", (20, 30, 1e-3, 200, 3.0, 3504.5, 1.44)),
    "stretch_ours_aniso20": ("cloth_stretch_ours", ["-mu2", "20", "-fiber2", "1,0", "-bending", "0"],
                             "anisotropic stretch, ours (b = [1,0])", (20, 20, 0, 200, 2.3, 11451.3, 0.37)),
    "stretch_ours_aniso80": ("cloth_stretch_ours", ["-mu2", "80", "-fiber", "1,0", "-fiber2", "1,3", "-bending", "0"],
                             "anisotropic stretch, ours (a = [1,0], b = [1,3])", (20, 80, 0, 200, 2.3, 41532.4, 0.42)),
    "stretch_bw_aniso20": ("cloth_stretch_bw", ["-mu2", "20", "-fiber2", "1,0", "-bending", "0"],
                           "anisotropic stretch, Kim 2020 (b = [1,0])", (20, 20, 0, 200, 5.3, 5759.5, 1.08)),
    "stretch_bw_aniso80": ("cloth_stretch_bw", ["-mu2", "80", "-fiber", "1,0", "-fiber2", "1,3", "-bending", "0"],
                           "anisotropic stretch, Kim 2020 (a = [1,0], b = [1,3])", (20, 80, 0, 200, 3.7, 5451.1, 1.10)),
}


# Table 1 scenes rendered to bench/results/images/<scene>_{rest,final}.png: (output step to draw, -output_every);
# step None = the last one.
RENDER = {
    "bunny_guided": (10, 5),            # t = 0.5: ears grown, body squashed
    "bunny_interact": (100, 50),        # handles fully pushed in
    "bunny_caricature": (None, 1000000),
    "armadillo_caricature": (None, 1000000),
}


def generate(name, size, h5=False):
    """The cached mesh's path (meshes/generate.sh NAME SIZE); with h5, its HDF5 copy (meshes/generate.sh h5 ...,
    converted once by the aries $ARIES_BIN, default build/aries)."""
    out = subprocess.run([os.path.join(ROOT, "meshes", "generate.sh")] + (["h5"] if h5 else []) + [name, size],
                         capture_output=True, text=True)
    if out.returncode != 0:
        sys.exit("mesh generation failed: " + out.stderr[-2000:])
    return out.stdout.strip().splitlines()[-1]


def machine_line(ranks):
    cpu = "?"
    for line in open("/proc/cpuinfo"):
        if line.startswith("model name"):
            cpu = line.split(":", 1)[1].strip()
            break
    return "%d MPI ranks on %s (%d cores), %s" % (ranks, cpu, os.cpu_count(), platform.platform())


def read_stats(stats):
    """The rows of a stats file and the aries builds named in its header lines ('aries 0.1.0 (git X)', then
    'aries 0.1.0 (git Y) from step N' for each restart from a checkpoint)."""
    with open(stats) as fh:
        lines = fh.read().splitlines()
    builds = [l[1:].strip() for l in lines if l.startswith("# aries")]  # a resumed run names each build and its start
    build = "; ".join(builds) if builds else "aries (build not recorded)"
    return list(csv.DictReader(l for l in lines if not l.startswith("#"))), build


def run_scene(a, env, name, opts, extra, msh, total_steps):
    """Runs one scene; returns (stats rows, output base, the build of a row read back (--reuse) or None)."""
    work = os.path.join(a.work, name)
    os.makedirs(work, exist_ok=True)
    stats = os.path.join(work, "stats.csv")
    base = os.path.join(work, name)
    checkpoint = base + ".checkpoint.h5"
    want = min(a.steps, total_steps) if a.steps else total_steps
    # a checkpoint left behind means a run cut short, unless the run stopped at --steps on purpose (run_scene keeps it)
    if a.reuse and os.path.exists(stats) and (want < total_steps or not os.path.exists(checkpoint)):
        rows, build = read_stats(stats)
        if len(rows) == want:
            print("%s: read back %d steps from %s (%s)" % (name, len(rows), stats, build), flush=True)
            return rows, base, build
    args = ["-options_file", os.path.join(ROOT, "options", opts + ".yml"), "-dm_plex_filename", msh] + extra
    text = open(os.path.join(ROOT, "options", opts + ".yml")).read()
    if "fiber_file" in text:
        args += ["-fiber_file", msh[:-4] + ".fibers"]
    if "target_file" in text:
        args += ["-target_file", msh[:-4] + ".targets"]
    args += ["-stats", stats, "-output", base, "-output_every", str(RENDER.get(name, (None, 1000000))[1])]
    resuming = a.resume and os.path.exists(checkpoint)
    if a.resume:  # a run cut short (session end, kill) continues from its last checkpoint on the next --resume
        args += ["-checkpoint_every", str(a.resume), "-checkpoint", checkpoint] + (["-restart", checkpoint] if resuming
                                                                                  else [])
    if a.steps:
        args += ["-steps", str(min(a.steps, total_steps))]
        if not re.search(r"^bc_ramp_steps:", text, re.M):  # keep the full-length ramp unless the scene sets its own
            args += ["-bc_ramp_steps", str(total_steps)]
    cmd = ["mpiexec", "-n", str(a.ranks), "--bind-to", "none", os.path.join(a.build, "aries")] + args
    print("$ " + " ".join(cmd), flush=True)
    log = os.path.join(work, "log.txt")
    with open(log, "a" if resuming else "w") as fh:  # streamed: a long run's progress can be followed there
        p = subprocess.run(cmd, cwd=ROOT, env=env, stdout=fh, stderr=subprocess.STDOUT)
    if not os.path.exists(stats):
        sys.exit("%s wrote no stats (exit %d); its log: %s" % (name, p.returncode, log))
    if p.returncode == 0 and os.path.exists(checkpoint) and want == total_steps:
        os.remove(checkpoint)  # finished: a later --resume starts this scene afresh
    # stopped at --steps short of the scene's length: the checkpoint stays, and a later --resume with more --steps
    # continues from it (the scene's full length run in parts, a session at a time)
    summary = [l for l in open(log).read().splitlines() if l.startswith("aries:")]
    print("\n".join(summary[-3:]), flush=True)
    rows, build = read_stats(stats)
    return rows, base, (build if resuming else None)  # a resumed row names the builds that ran its parts


CONVERGED = ("newton_step", "converged_initial", "step_bound", "energy_roundoff")


def averages(st):
    """Per step over every step run: Newton updates, linear solves, PCG iterations, seconds; and the failed steps."""
    k = max(len(st), 1)
    return (sum(int(r["newton_its"]) for r in st) / k, sum(int(r.get("linear_solves", r["newton_its"])) for r in st) / k,
            sum(int(r["ksp_its"]) for r in st) / k, sum(float(r["wall_s"]) for r in st) / k,
            sum(1 for r in st if r["reason"].split("|")[0] not in CONVERGED))


def yml_value(opts, key, extra):
    if "-" + key in extra:
        return extra[extra.index("-" + key) + 1]
    m = re.search(r"^%s:\s*(\S+)" % key, open(os.path.join(ROOT, "options", opts + ".yml")).read(), re.M)
    return m.group(1) if m else "-"


def commit_line():
    """'commit X' of HEAD, '+ uncommitted changes' when tracked files other than the results differ from it."""
    head = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                          text=True).stdout.strip() or "?"
    dirty = subprocess.run(["git", "-C", ROOT, "status", "--porcelain", "--untracked-files=no", "--", ".",
                            ":!bench/results", ":!docs/results*.md", ":!docs/images"],
                           capture_output=True, text=True).stdout.strip()
    return "commit %s%s" % (head, " + uncommitted changes" if dirty else "")


def write(path, lines):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path + ".tmp", "w") as fh:
        fh.write("\n".join(lines))
    os.replace(path + ".tmp", path)
    print("wrote " + path)


def parse_ranges(text):
    """'A-B,C-D' -> [(A, B), (C, D)], each 1 <= A <= B."""
    ranges = []
    for item in text.split(",") if text else []:
        m = re.fullmatch(r"(\d+)-(\d+)", item.strip())
        if not m or not 1 <= int(m.group(1)) <= int(m.group(2)):
            sys.exit("scenes.py: --ranges: '%s' is not a range of steps A-B with 1 <= A <= B" % item)
        ranges.append((int(m.group(1)), int(m.group(2))))
    return ranges


def range_rows(name, st, ranges):
    """The table rows of one scene's averages over each range of steps (the steps of the range that were run)."""
    rows = []
    for lo, hi in ranges:
        part = [r for r in st if lo <= int(r["step"]) <= hi]
        if part:
            newton, solves, pcg, secs, failed = averages(part)
            rows.append("| %s | %d-%d | %d | %.2f | %.2f | %.1f | %.3f | %d |"
                        % (name, lo, hi, len(part), newton, solves, pcg, secs, failed))
        else:
            rows.append("| %s | %d-%d | 0 | - | - | - | - | - |" % (name, lo, hi))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scenes", nargs="*")
    ap.add_argument("--table", type=int, choices=[1, 2], default=1)
    ap.add_argument("--steps", type=int, default=None)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=None)
    ap.add_argument("--work", default=os.path.join(ROOT, "out", "bench"))
    ap.add_argument("--resume", type=int, default=0, metavar="K",
                    help="checkpoint every K steps and continue a scene cut short from its last checkpoint (0: off)")
    ap.add_argument("--reuse", action="store_true",
                    help="read a finished scene (stats for every step, no checkpoint) back instead of running it again")
    ap.add_argument("--options", default="", metavar="'ARIES OPTIONS'",
                    help="aries options added to every scene's command line, after the scene's own")
    ap.add_argument("--ranges", default="", metavar="A-B,...",
                    help="also average over these ranges of steps (a table of its own)")
    a = ap.parse_args()
    added = shlex.split(a.options)
    if added and not added[0].startswith("-"):
        sys.exit("scenes.py: --options '%s' must begin with an aries option (-name)" % a.options)
    ranges = parse_ranges(a.ranges)
    catalog = SCENES if a.table == 1 else CLOTH
    names = a.scenes or list(catalog)
    for n in names:
        if n not in catalog:
            sys.exit("unknown scene %s for table %d (known: %s)" % (n, a.table, ", ".join(catalog)))
    out_path = a.out or os.path.join(ROOT, "bench", "results", "table%d.md" % a.table)
    env = dict(os.environ, OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_mpi_yield_when_idle="1")
    if os.geteuid() == 0:
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    reused = []
    by_range = []  # --ranges: each scene's rows, a table after the main one
    # checked before the runs: a commit made while they run must not be credited with their numbers
    date = "%s UTC at %s" % (datetime.datetime.utcnow().strftime("%Y-%m-%d %H:%M"), commit_line())
    command = " ".join(["bench/scenes.py"] + [shlex.quote(x) for x in sys.argv[1:]])  # as given (--resume, --out)
    steps_note = (["Averages are over the first %d steps of each scene (prescribed motions keep their full-length ramp), "
                   "not over the whole run.\n" % a.steps] if a.steps else [])
    if a.table == 1:
        out = ["# Table 1: volumetric scenes, aries vs the paper\n",
               "Generated by `%s` on %s, %s. Paper: 20-core 3.8 GHz i9, Eigen PCG + "
               "diagonal preconditioner, same Newton tolerance (1e-2 L dt) and PCG tolerance (1e-6). Each row's "
               "density (kg/m^3) is its options file's: at 1000, most scenes' density, the inertia term dominates at "
               "dt = 1e-2 and CG needs far fewer iterations than the paper's stiffness-dominated runs (its density is "
               "not stated); the `_rho1` rows run the same scenes at density 1, "
               "the stiffness-dominated regime the paper's PCG counts point to. Newton = updates of the state per step, "
               "solves = linear solves per step (the one that certifies convergence included), averaged over every "
               "step run.\n"
               % (command, date, machine_line(a.ranks)),
               "| scene | elements | E | nu | density | dt | steps run / total | Newton/step | solves/step | PCG/step | s/step | "
               "failed steps | paper: elements | Newton/step | PCG/step | s/step |",
               "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for n in names:
            opts, extra, (mname, msize), paper = SCENES[n]
            msh = generate(mname, msize)
            with open(msh[:-4] + ".json") as fh:
                info = json.load(fh)
                elems = info["tets"] if "tets" in info else info["hexes"]
            extra = extra + added
            st, base, build = run_scene(a, env, n, opts, extra, msh, paper[4])
            newton, solves, pcg, secs, failed = averages(st)
            by_range += range_rows(n, st, ranges)
            if build:
                reused.append("%s (%s)" % (n, build))
            if n in RENDER:
                step = RENDER[n][0]
                step = step if step is not None and step <= len(st) else None
                img = os.path.join(ROOT, "bench", "results", "images")
                os.makedirs(img, exist_ok=True)
                for k, tag in ((0, "rest"), (step, "final")):
                    cmd = ["/usr/bin/python3", os.path.join(ROOT, "scripts", "render_png.py"), base,
                           os.path.join(img, "%s_%s.png" % (n, tag)), "--field", "displacement", "--view", "15,-120",
                           "--title", "%s (%s)" % (n, "rest" if k == 0 else "step %s" % (k or len(st)))]
                    if k is not None:
                        cmd += ["--step", str(k)]
                    subprocess.run(cmd, check=False)
            dt = paper[3] if yml_value(opts, "integrator", extra) == "beuler" else "static, %g" % paper[3]
            out.append("| %s | %s | %s | %s | %s | %s | %d / %d | %.2f | %.2f | %.1f | %.3f | %d | %d | %.1f | %.1f "
                       "| %.2f |"
                       % (n, elems, yml_value(opts, "E", extra), yml_value(opts, "nu", extra),
                          yml_value(opts, "density", extra), dt, len(st),
                          paper[4], newton, solves, pcg, secs, failed, paper[0], paper[5], paper[6], paper[7]))
    else:
        img = os.path.join(ROOT, "bench", "results", "images")
        os.makedirs(img, exist_ok=True)
        msh = generate("cloth", "default")
        with open(msh[:-4] + ".json") as fh:
            tris = json.load(fh)["triangles"]
        out = ["# Table 2: cloth ({:,} triangles, dt = 1e-2), aries vs the paper\n".format(tris),
               "Generated by `%s` on %s, %s. Areal density 0.1 kg/m^2, gravity 9.8; the "
               "paper's bending is 1e-3 (0 for its anisotropic stretch rows). Snapshots of the final states: "
               "`bench/results/images/cloth_<scene>.png`.\n" % (command, date, machine_line(a.ranks)),
               "| scene | model | stretch | shear | bending | steps run / total | Newton/step | solves/step | PCG/step | "
               "s/step | failed steps | paper: Newton/step | PCG/step | s/step |",
               "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for n in names:
            opts, extra, label, paper = CLOTH[n]
            extra = extra + added
            st, base, build = run_scene(a, env, n, opts, extra + ["-dm_plex_gmsh_spacedim", "3"], msh, paper[3])
            newton, solves, pcg, secs, failed = averages(st)
            by_range += range_rows(n, st, ranges)
            if build:
                reused.append("%s (%s)" % (n, build))
            out.append("| %s | %s | %s | %s | %s | %d / %d | %.2f | %.2f | %.1f | %.3f | %d | %.1f | %.1f | %.2f |"
                       % (n, label, yml_value(opts, "mu1", extra),
                          yml_value(opts, "mu1" if yml_value(opts, "energy", extra) == "bw46" else "mu2", extra),
                          yml_value(opts, "bending", extra), len(st), paper[3], newton, solves, pcg, secs, failed,
                          paper[4], paper[5], paper[6]))
            subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "scripts", "render_png.py"), base,
                            os.path.join(img, "cloth_%s.png" % n), "--field", "displacement", "--view", "30,-60",
                            "--title", "%s (step %d)" % (label, len(st))], check=False)
    out.append("")
    out += steps_note
    if ranges:
        out += ["## By range of steps\n", "The same averages over each range of steps (of the steps run in it).\n",
                "| scene | steps | run | Newton/step | solves/step | PCG/step | s/step | failed steps |",
                "|---|---|---:|---:|---:|---:|---:|---:|"] + by_range + [""]
    if reused:
        out.append("Rows read back from an earlier run of this script (`--reuse`) or continued from a checkpoint "
                   "(`--resume`), with the aries builds that ran them (and the step each took over at): %s.\n"
                   % "; ".join(reused))
    write(out_path, out)


if __name__ == "__main__":
    main()
