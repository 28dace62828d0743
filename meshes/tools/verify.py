#!/usr/bin/python3
"""Check a mesh file against the contract the aries solver relies on (meshes/README.md):

    verify.py MESH.msh [MESH.fibers]

Common: MSH 2.2 ASCII, nodes 1..n; every element has a physical tag > 0; $PhysicalNames names every
physical tag that is used, per dimension; point elements (physical points) reference existing nodes.
The top-dimensional elements decide the kind:
- tetrahedral mesh: every node is used by a tetrahedron; every tetrahedron has positive volume;
  triangles (physical surfaces) are boundary faces of the tets; no line elements;
- triangle (surface) mesh: no tetrahedra; every node is used by a triangle; no degenerate triangle;
  edge- and vertex-manifold and consistently oriented (every interior edge used once in each
  direction); lines (physical curves) are boundary edges, directed as in their triangle; a planar
  mesh has all its normals on the same side (reported);
- the fibers file, if given: '#' comments, N = number of cells, N unit vectors.
Prints a summary; exits 1 on the first violation.
"""

import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import meshkit as mk  # noqa: E402

NPE = {15: 1, 1: 2, 2: 3, 4: 4}  # nodes per element of the element types we accept


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
    groups = {t: ([], []) for t in NPE}
    for line in lines[i + 2:i + 2 + m]:
        p = [int(v) for v in line.split()]
        if p[1] not in groups:
            fail("unexpected element type %d" % p[1])
        nt = p[2]
        if nt < 1 or p[3] <= 0:
            fail("element %d has no physical tag" % p[0])
        if len(p) != 3 + nt + NPE[p[1]]:
            fail("element %d has %d nodes (type %d needs %d)" % (p[0], len(p) - 3 - nt, p[1], NPE[p[1]]))
        groups[p[1]][0].append(p[3])
        groups[p[1]][1].append(p[3 + nt:])
    g = {}
    for t, (tags, conn) in groups.items():
        C = np.array(conn, dtype=np.int64).reshape(-1, NPE[t]) - 1
        if len(C) and (C.min() < 0 or C.max() >= n):
            fail("type %d elements reference nodes outside 1..%d" % (t, n))
        g[t] = (np.array(tags, dtype=np.int64), C)
    return names, X, g


def check_names(names, pairs):
    for dim, tags in pairs:
        for t in sorted(set(tags.tolist())):
            if (dim, t) not in names:
                fail("physical tag %d (dim %d) has no $PhysicalNames entry" % (t, dim))


def verify_tets(path, names, X, g):
    ptag, P = g[15]
    ftag, F = g[2]
    ctag, T = g[4]
    if len(g[1][0]):
        fail("line elements in a tetrahedral mesh")
    used = np.zeros(len(X), dtype=bool)
    used[T.ravel()] = True
    if not used.all():
        fail("%d nodes are not used by any tetrahedron" % (~used).sum())
    vol = mk.signed_volumes(X, T)
    if (vol <= 0).any():
        fail("%d tetrahedra with non-positive volume" % (vol <= 0).sum())
    check_names(names, ((3, ctag), (2, ftag), (0, ptag)))
    m = mk.TetMesh(X, T)
    if len(F):
        B, _ = m.boundary_faces()
        bset = set(map(tuple, np.sort(B, axis=1).tolist()))
        bad = [f for f in np.sort(F, axis=1).tolist() if tuple(f) not in bset]
        if bad:
            fail("%d triangles are not boundary faces of the tets" % len(bad))
    print("%s: OK  %d tets, %d vertices, volume %.6g, min quality %.3f"
          % (path, len(T), len(X), vol.sum(), mk.tet_quality(X, T).min()))
    kinds = {3: ("volume", ctag, "tets"), 2: ("surface", ftag, "triangles"), 0: ("point", ptag, "vertices")}
    return len(T), kinds


def verify_tris(path, names, X, g):
    ptag, P = g[15]
    ltag, L = g[1]
    ctag, T = g[2]
    used = np.zeros(len(X), dtype=bool)
    used[T.ravel()] = True
    if not used.all():
        fail("%d nodes are not used by any triangle" % (~used).sum())
    check_names(names, ((2, ctag), (1, ltag), (0, ptag)))
    m = mk.TriMesh(X, T)
    A = m.areas()
    tol = 1e-12 * np.ptp(X, axis=0).max() ** 2
    if (A <= tol).any():
        fail("%d degenerate triangles (area <= %g)" % ((A <= tol).sum(), tol))
    t = m.topology()
    if t["nonmanifold_edges"] or t["nonmanifold_vertices"]:
        fail("%d non-manifold edges, %d non-manifold vertices" % (t["nonmanifold_edges"], t["nonmanifold_vertices"]))
    if not t["consistently_oriented"]:
        fail("triangles are not consistently oriented")
    if len(L):
        B = m.boundary_edges()
        n = len(X)
        bdir = set((B[:, 0] * n + B[:, 1]).tolist())
        bund = bdir | set((B[:, 1] * n + B[:, 0]).tolist())
        key = (L[:, 0] * n + L[:, 1]).tolist()
        notb = sum(k not in bund for k in key)
        if notb:
            fail("%d line elements are not boundary edges" % notb)
        rev = sum(k not in bdir for k in key)
        if rev:
            fail("%d boundary lines are directed against their triangle" % rev)
    N = m.area_vectors()
    side = ""
    if np.ptp(X[:, 2]) == 0.0:
        up = int((N[:, 2] > 0).sum())
        side = ", planar z = %g, normals: %d +z, %d -z" % (X[0, 2], up, len(T) - up)
        if 0 < up < len(T):
            fail("planar mesh with normals on both sides")
    print("%s: OK  %d triangles, %d vertices, area %.6g, min quality %.3f, Euler characteristic %d, "
          "%d component(s), %d boundary loop(s) %s, consistently oriented%s"
          % (path, len(T), len(X), A.sum(), mk.triangle_quality(X, T).min(), t["euler_characteristic"],
             t["components"], t["boundary_loops"], t["boundary_loop_lengths"], side))
    kinds = {2: ("surface", ctag, "triangles"), 1: ("curve", ltag, "edges"), 0: ("point", ptag, "vertices")}
    return len(T), kinds


def main(argv):
    if not argv:
        raise SystemExit(__doc__)
    names, X, g = parse(argv[0])
    if len(g[4][1]):
        ncells, kinds = verify_tets(argv[0], names, X, g)
    elif len(g[2][1]):
        ncells, kinds = verify_tris(argv[0], names, X, g)
    else:
        fail("no tetrahedra and no triangles")
    for (dim, tag), name in sorted(names.items()):
        if dim not in kinds:
            fail("physical name for dimension %d, which this mesh does not use" % dim)
        kind = kinds[dim]
        cnt = int((kind[1] == tag).sum())
        if cnt == 0:
            fail("physical group %d %s (dim %d) is empty" % (tag, name, dim))
        print("  physical %-7s %2d %-14s %8d %s" % (kind[0], tag, '"%s"' % name, cnt, kind[2]))
    if len(argv) > 1:
        with open(argv[1]) as f:
            data = [l for l in f.read().splitlines() if l and not l.startswith("#")]
        n = int(data[0])
        A = np.array([l.split() for l in data[1:]], dtype=float)
        if n != ncells or A.shape != (ncells, 3):
            fail("fibers: %d / %s entries for %d cells" % (n, A.shape, ncells))
        if np.abs(np.linalg.norm(A, axis=1) - 1).max() > 1e-12:
            fail("fibers are not unit vectors")
        print("  fibers: %d unit vectors" % n)


if __name__ == "__main__":
    main(sys.argv[1:])
