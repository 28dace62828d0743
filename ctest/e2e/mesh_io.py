"""End-to-end cases: mesh input (gmsh face labels made serially or after distribution, MSH 2.2 and 4.1) and parallel
HDF5 mesh input and output."""
import glob
import os
import re
import subprocess

import h5py
import numpy as np

from harness import fail, step_file, step_positions
from .common import ARGS, mesh, out_base, read_state, run


def msh41_from_msh22(src, dst):
    """The MSH 2.2 ASCII mesh src rewritten as MSH 4.1 ASCII (one entity per element dimension and physical tag, the
    physical names kept): the same mesh in the format whose tags live on entities."""
    text = open(src).read()
    names = text[text.index("$PhysicalNames"):text.index("$EndPhysicalNames") + len("$EndPhysicalNames")]
    nodes = text[text.index("$Nodes") + 7:text.index("$EndNodes")].split("\n")[1:]
    nodes = [l.split() for l in nodes if l.strip()]
    elements = text[text.index("$Elements") + 10:text.index("$EndElements")].split("\n")[1:]
    dims = {15: 0, 1: 1, 2: 2, 3: 2, 4: 3, 5: 3}
    blocks = {}  # (dim, physical tag, type) -> element node lists
    for l in elements:
        v = [int(x) for x in l.split()]
        if not v:
            continue
        ntags = v[2]
        blocks.setdefault((dims[v[1]], v[3] if ntags else 0, v[1]), []).append(v[3 + ntags:])
    entities = sorted({(d, t) for d, t, _ in blocks})
    ids = {e: i + 1 for i, e in enumerate(entities)}
    out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", names, "$Entities",
           " ".join(str(sum(1 for d, _ in entities if d == k)) for k in range(4))]
    for d, t in entities:
        phys = "1 %d" % t if t else "0"
        out.append("%d 0 0 0 %s" % (ids[(d, t)], phys) if d == 0 else "%d 0 0 0 1 1 1 %s 0" % (ids[(d, t)], phys))
    out += ["$EndEntities", "$Nodes", "1 %d 1 %d" % (len(nodes), max(int(n[0]) for n in nodes)),
            "3 %d 0 %d" % (ids[entities[-1]], len(nodes))]
    out += [n[0] for n in nodes] + [" ".join(n[1:]) for n in nodes] + ["$EndNodes", "$Elements"]
    count = sum(len(b) for b in blocks.values())
    out.append("%d %d 1 %d" % (len(blocks), count, count))
    eid = 0
    for (d, t, typ), cells in blocks.items():
        out.append("%d %d %d %d" % (d, ids[(d, t)], typ, len(cells)))
        for c in cells:
            eid += 1
            out.append("%d %s" % (eid, " ".join(map(str, c))))
    out += ["$EndElements", ""]
    with open(dst, "w") as fh:
        fh.write("\n".join(out))
    return dst


def mesh_labels(msh, faces, tag):
    """The label strata of the mesh as read on one rank (-dm_view), every label but depth and celltype."""
    info = os.path.join(ARGS.work, tag + ".info")
    log, _ = run(["-dm_plex_filename", msh, "-integrator", "static", "-steps", "1", "-mesh_faces",
                  faces, "-dm_view", "-info", info + ":sys"], ranks=1, tag=tag)
    info_text = "".join(open(f).read() for f in glob.glob(info + "*"))
    if ("faces and edges made by every rank after distribution" in info_text) != (faces == "distributed"):
        fail("%s: -mesh_faces %s did not take its path (the -info line)" % (msh, faces))
    block = log[log.index("Labels:"):].splitlines()[1:]
    lines = []
    for l in block:
        if not l.startswith("  ") or l.startswith("   "):
            break
        if not l.strip().startswith(("depth", "celltype")):
            lines.append(l.strip())
    return sorted(lines)


def case_mesh_faces():
    """A 3D gmsh mesh's faces made by every rank after distribution (-mesh_faces distributed, the default) label the
    same faces as PETSc's reader does on rank 0 (-mesh_faces serial): the label strata agree on tetrahedra and
    hexahedra in MSH 2.2, on the tetrahedra rewritten as MSH 4.1 (tags on entities), and on both meshes converted to
    HDF5 (read in parallel, its face rows kept until the faces exist); and on --ranks ranks the box compressed by its
    face groups has the same held vertices and the same reaction in both modes, from the .msh and from the .h5 (the
    partitions differ: METIS gets the dual graph from the corners instead of the faces, the .h5 is cut by RCB)."""
    box, hexcube = mesh("box"), mesh("hexcube")
    meshes = [box, hexcube, msh41_from_msh22(box, os.path.join(ARGS.work, "box41.msh"))]
    h5 = {box: h5_mesh("box"), hexcube: h5_mesh("hexcube")}
    for k, msh in enumerate(meshes):
        serial = mesh_labels(msh, "serial", "labels_serial_%d" % k)
        distributed = mesh_labels(msh, "distributed", "labels_distributed_%d" % k)
        print("%s: %s" % (os.path.basename(msh), "; ".join(serial)))
        if not any(l.startswith("Face Sets") for l in serial):
            fail("%s: no Face Sets read by PETSc's reader: the comparison proves nothing" % msh)
        if serial != distributed:
            fail("%s: labels differ:\n serial      %s\n distributed %s" % (msh, serial, distributed))
        if msh in h5:
            for faces in ("serial", "distributed"):
                from_h5 = mesh_labels(h5[msh], faces, "labels_h5_%s_%d" % (faces, k))
                if from_h5 != serial:
                    fail("%s -mesh_faces %s: labels differ from the .msh's:\n .msh %s\n .h5  %s"
                         % (h5[msh], faces, serial, from_h5))
    results = {}
    for source, m in (("msh", meshes[2]), ("h5", h5[box])):
        for faces in ("serial", "distributed"):
            tag = "box_%s_%s" % (source, faces)
            log, _ = run(["-dm_plex_filename", m, "-energy", "iarap", "-integrator", "static", "-steps", "1",
                          "-bc_clamp", "bottom,top", "-bc_clamp_top_translate", "0,0,-0.1", "-mesh_faces", faces,
                          "-reactions", out_base(tag) + "_reactions.csv"], tag=tag)
            held = re.search(r"\((\d+) Dirichlet\)", log)
            force = [float(x) for x in
                     open(out_base(tag) + "_reactions.csv").read().strip().splitlines()[-1].split(",")[3:]]
            results[tag] = (int(held.group(1)) if held else -1, np.array(force))
    print("held vertices and top reaction: %s" % results)
    held_s, force_s = results["box_msh_serial"]
    for tag, (held, force) in results.items():
        if held_s <= 0 or held != held_s:
            fail("held vertices: %s %d, box_msh_serial %d" % (tag, held, held_s))
        if not np.abs(force - force_s).max() <= 1e-8 * np.abs(force_s).max():
            fail("top reaction: %s %s, box_msh_serial %s" % (tag, force, force_s))


def h5_mesh(name):
    """The HDF5 copy of a test mesh (meshes/generate.sh h5, converted by the aries under test)."""
    env = dict(os.environ, ARIES_BIN=ARGS.aries)
    p = subprocess.run([os.path.join(ARGS.root, "meshes", "generate.sh"), "h5", name, "test"], capture_output=True,
                       text=True, env=env)
    if p.returncode != 0:
        fail("meshes/generate.sh h5 %s test failed: %s" % (name, p.stderr[-2000:]))
    return p.stdout.strip().splitlines()[-1]


def h5_datasets(path):
    out = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: out.__setitem__(n, o[()]) if isinstance(o, h5py.Dataset) else None)
    return out


def case_parallel_io():
    """Parallel mesh input and collective output. The shell (pressure on a face group) and the cloth (triangles in 3D,
    one overlap layer) converted to HDF5 by meshes/generate.sh h5: on 1 rank the .h5 run writes the very bytes' values
    of the .msh run (every dataset equal); on 2 and 3 ranks (RCB partitions, uneven output blocks) the mesh
    datasets and markers are equal and the states agree to 1e-8 L; a checkpoint written on 3 ranks restarts on 1 rank
    from the .msh and ends within 1e-8 L of the uninterrupted run. The armadillo's point group (pinned vertices) marks
    the same vertices from the .h5 on 3 ranks as from the .msh."""
    shell_msh, shell_h5 = mesh("shell"), h5_mesh("shell")
    common = ["-options_file", os.path.join(ARGS.root, "options", "sphere_inflate.yml"), "-steps", "3",
              "-bc_ramp_steps", "3", "-newton_tol", "1e-10", "-output_fields", "all", "-strict"]
    bases = {}
    for label, m, n in (("msh1", shell_msh, 1), ("h5_1", shell_h5, 1), ("h5_2", shell_h5, 2), ("h5_3", shell_h5, 3)):
        tag = "pio_shell_" + label
        run(common + ["-dm_plex_filename", m, "-output", out_base(tag), "-stats", out_base(tag) + ".csv",
                      "-checkpoint_every", "2", "-checkpoint", out_base(tag) + ".ck.h5"], ranks=n, tag=tag)
        bases[label] = out_base(tag)
    L = None
    for label in ("h5_1", "h5_2", "h5_3"):
        for rel in (".h5", ".steps/%s_000003.h5", ".ck.h5"):
            a = bases["msh1"] + (rel % os.path.basename(bases["msh1"]) if "%" in rel else rel)
            b = bases[label] + (rel % os.path.basename(bases[label]) if "%" in rel else rel)
            da, db = h5_datasets(a), h5_datasets(b)
            if sorted(da) != sorted(db):
                fail("%s: datasets %s, the .msh run's %s" % (b, sorted(db), sorted(da)))
            if L is None:
                rest = da["mesh/rest"]
                L = np.linalg.norm(rest.max(0) - rest.min(0))
            for k in da:
                if da[k].shape != db[k].shape:
                    fail("%s:%s has shape %s, the .msh run's %s" % (b, k, db[k].shape, da[k].shape))
                exact = np.array_equal(da[k], db[k], equal_nan=True)
                if label == "h5_1" or k in ("mesh/topology", "mesh/rest", "vertex/marker", "cell/region"):
                    if not exact:
                        fail("%s:%s differs from the .msh run's (must be equal)" % (b, k))
                elif k in ("positions", "displacement"):
                    d = np.abs(da[k] - db[k]).max() / L
                    print("%s %s: max difference %.2e L" % (label, k, d))
                    if not d <= 1e-8:
                        fail("%s:%s differs by %.3e L (limit 1e-8)" % (b, k, d))
    # a checkpoint written on 3 ranks after step 2 of 3, restarted on 1 rank from the .msh
    tag = "pio_shell_stop2"
    run(common + ["-dm_plex_filename", shell_h5, "-steps", "2", "-checkpoint_every", "2", "-checkpoint",
                  out_base(tag) + ".ck.h5"], ranks=3, tag=tag)
    ck = out_base(tag) + ".ck.h5"
    tag = "pio_shell_restart"
    run(common + ["-dm_plex_filename", shell_msh, "-output", out_base(tag), "-restart", ck], ranks=1, tag=tag)
    x0 = step_positions(bases["msh1"], 3)
    x1 = step_positions(out_base(tag), 3)
    d = np.abs(x0 - x1).max() / L
    print("restart of the 3-rank checkpoint on 1 rank: %.2e L" % d)
    if not d <= 1e-8:
        fail("the restart differs by %.3e L" % d)
    # a gmsh point group (Vertex Sets: the armadillo's pinned hands and feet) read from the .h5 on 3 ranks pins the
    # same vertices as the .msh on 1
    arm = ["-options_file", os.path.join(ARGS.root, "options", "armadillo_scramble.yml"), "-steps", "1",
           "-output_every", "1", "-output_fields", "all", "-strict"]
    markers = []
    for label, m, n in (("msh1", mesh("armadillo"), 1), ("h5_3", h5_mesh("armadillo"), 3)):
        tag = "pio_armadillo_" + label
        run(arm + ["-dm_plex_filename", m, "-output", out_base(tag), "-stats", out_base(tag) + ".csv"], ranks=n,
            tag=tag)
        with h5py.File(step_file(out_base(tag), 0), "r") as f:
            markers.append(f["vertex/marker"][()])
    if not np.array_equal(markers[0], markers[1]) or not markers[0].any():
        fail("armadillo: the .h5 run on 3 ranks pins other vertices than the .msh run (vertex/marker differs)")
    # cloth: triangles in 3D, distributed with an overlap layer
    cloth = ["-options_file", os.path.join(ARGS.root, "options", "cloth_stretch_ours.yml"), "-steps", "5",
             "-output_every", "5", "-strict"]
    states = []
    for label, m, n in (("msh1", mesh("cloth"), 1), ("h5_2", h5_mesh("cloth"), 2)):
        tag = "pio_cloth_" + label
        run(cloth + ["-dm_plex_filename", m, "-output", out_base(tag), "-stats", out_base(tag) + ".csv"], ranks=n,
            tag=tag)
        states.append(step_positions(out_base(tag), 5))
    rest, _, _, _ = read_state(out_base("pio_cloth_msh1"))
    d = np.abs(states[0] - states[1]).max() / np.linalg.norm(rest.max(0) - rest.min(0))
    print("cloth, .msh on 1 rank vs .h5 on 2: %.2e L" % d)
    if not d <= 1e-8:
        fail("cloth from the .h5 on 2 ranks differs by %.3e L" % d)


CASES = {
    "mesh_faces": case_mesh_faces,
    "parallel_io": case_parallel_io,
}
