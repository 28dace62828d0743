#!/usr/bin/python3
"""Check a mesh file against the contract the aries solver relies on (meshes/README.md):

    verify.py MESH.msh [MESH.fibers]

- MSH 2.2 ASCII; $PhysicalNames names every physical tag that is used, per dimension;
- every node is used by a tetrahedron; every tetrahedron has positive volume and a physical volume;
- triangles (physical surfaces) are boundary faces of the tets; point elements (physical points)
  reference existing nodes;
- the fibers file, if given: '#' comments, N = number of tets, N unit vectors.
Prints a summary; exits 1 on the first violation.
"""

import sys

import numpy as np

sys.path.insert(0, __import__("os").path.dirname(__import__("os").path.abspath(__file__)))
import meshkit as mk  # noqa: E402


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def parse(path):
    with open(path) as f:
        lines = f.read().splitlines()
    if lines[:3] != ["$MeshFormat", "2.2 0 8", "$EndMeshFormat"]:
        fail("%s: not MSH 2.2 ASCII" % path)
    names = {}
    i = lines.index("$PhysicalNames") if "$PhysicalNames" in lines else None
    if i is not None:
        for line in lines[i + 2:i + 2 + int(lines[i + 1])]:
            d, t, n = line.split(None, 2)
            names[(int(d), int(t))] = n.strip('"')
    i = lines.index("$Nodes")
    n = int(lines[i + 1])
    X = np.array([l.split()[1:4] for l in lines[i + 2:i + 2 + n]], dtype=float)
    ids = [int(l.split()[0]) for l in lines[i + 2:i + 2 + n]]
    if ids != list(range(1, n + 1)):
        fail("node ids are not 1..n")
    i = lines.index("$Elements")
    m = int(lines[i + 1])
    groups = {15: ([], []), 2: ([], []), 4: ([], [])}
    for line in lines[i + 2:i + 2 + m]:
        p = [int(v) for v in line.split()]
        if p[1] not in groups:
            fail("unexpected element type %d" % p[1])
        nt = p[2]
        if nt < 1:
            fail("element %d has no physical tag" % p[0])
        groups[p[1]][0].append(p[3])
        groups[p[1]][1].append(p[3 + nt:])
    return names, X, {k: (np.array(v[0], dtype=np.int64), np.array(v[1], dtype=np.int64) - 1)
                      for k, v in groups.items()}


def main(argv):
    if not argv:
        raise SystemExit(__doc__)
    names, X, g = parse(argv[0])
    ptag, P = g[15]
    ftag, F = g[2]
    ctag, T = g[4]
    T = T.reshape(-1, 4)
    if len(T) == 0:
        fail("no tetrahedra")
    used = np.zeros(len(X), dtype=bool)
    used[T.ravel()] = True
    if not used.all():
        fail("%d nodes are not used by any tetrahedron" % (~used).sum())
    vol = mk.signed_volumes(X, T)
    if (vol <= 0).any():
        fail("%d tetrahedra with non-positive volume" % (vol <= 0).sum())
    for dim, tags in ((3, ctag), (2, ftag), (0, ptag)):
        for t in sorted(set(tags.tolist())):
            if (dim, t) not in names:
                fail("physical tag %d (dim %d) has no $PhysicalNames entry" % (t, dim))
    m = mk.TetMesh(X, T)
    if len(F):
        B, _ = m.boundary_faces()
        bset = set(map(tuple, np.sort(B, axis=1).tolist()))
        bad = [f for f in np.sort(F.reshape(-1, 3), axis=1).tolist() if tuple(f) not in bset]
        if bad:
            fail("%d triangles are not boundary faces of the tets" % len(bad))
    print("%s: OK  %d tets, %d vertices, volume %.6g, min quality %.3f"
          % (argv[0], len(T), len(X), vol.sum(), mk.tet_quality(X, T).min()))
    for (dim, tag), name in sorted(names.items()):
        kind = {3: ("volume", ctag, "tets"), 2: ("surface", ftag, "triangles"), 0: ("point", ptag, "vertices")}[dim]
        print("  physical %-7s %2d %-12s %8d %s" % (kind[0], tag, '"%s"' % name, (kind[1] == tag).sum(), kind[2]))
    if len(argv) > 1:
        with open(argv[1]) as f:
            data = [l for l in f.read().splitlines() if l and not l.startswith("#")]
        n = int(data[0])
        A = np.array([l.split() for l in data[1:]], dtype=float)
        if n != len(T) or A.shape != (len(T), 3):
            fail("fibers: %d / %s entries for %d tets" % (n, A.shape, len(T)))
        if np.abs(np.linalg.norm(A, axis=1) - 1).max() > 1e-12:
            fail("fibers are not unit vectors")
        print("  fibers: %d unit vectors" % n)


if __name__ == "__main__":
    main(sys.argv[1:])
