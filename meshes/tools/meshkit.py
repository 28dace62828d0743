"""Small, dependency-free (numpy only) mesh helpers for the aries mesh generators.

Everything here is deterministic: the same input arrays give the same output bytes.

Contents
- read_off / parse_off / read_tar_member : triangle surfaces in Geomview OFF format (optionally
  straight out of Debian's CGAL data.tar.gz, without unpacking it)
- write_surface_msh22 : a triangle surface as MSH 2.2 (input for gmsh's surface remeshing)
- read_msh22_tets : the nodes and tetrahedra of a gmsh MSH 2.2 ASCII file
- read_tetgen : the .node/.ele output of tetgen (not used by the presets, which mesh with gmsh
  because tetgen keeps every input surface triangle; handy for ad-hoc meshes: tetgen -pq1.414 x.off)
- TetMesh : a tetrahedral mesh with cell regions, boundary face sets and vertex sets, that can
  orient its tets, drop unused nodes, extract its boundary and write the MSH 2.2 file the solver reads
- write_cell_vectors : the per-cell side file format (fibers)
"""

import io
import os
import tarfile

import numpy as np

# gmsh MSH 2.2 element type numbers
MSH_POINT, MSH_TRI, MSH_TET = 15, 2, 4


# --------------------------------------------------------------------------------------------------
# Readers


def _parse_off(text):
    toks = []
    for line in text.splitlines():
        line = line.split("#", 1)[0].strip()
        if line:
            toks.extend(line.split())
    if not toks or toks[0] != "OFF":
        raise ValueError("not an OFF file (missing 'OFF' header)")
    nv, nf = int(toks[1]), int(toks[2])
    i = 4
    V = np.array(toks[i:i + 3 * nv], dtype=float).reshape(nv, 3)
    i += 3 * nv
    F = np.empty((nf, 3), dtype=np.int64)
    for k in range(nf):
        n = int(toks[i])
        if n != 3:
            raise ValueError("OFF face %d has %d vertices; only triangles are supported" % (k, n))
        F[k] = [int(toks[i + 1]), int(toks[i + 2]), int(toks[i + 3])]
        i += 1 + n
    return V, F


def read_off(path):
    """Vertices (n,3) float and triangles (m,3) int (0-based) of a triangle-only OFF file."""
    with open(path) as f:
        return _parse_off(f.read())


def read_tar_member(tar_path, member):
    """Bytes of one member of a (gzip) tarball, without unpacking the rest."""
    with tarfile.open(tar_path, "r:*") as tf:
        return tf.extractfile(member).read()


def parse_off(raw):
    """read_off for the bytes/str content of an OFF file."""
    return _parse_off(raw.decode("ascii") if isinstance(raw, bytes) else raw)


def read_msh22_tets(path):
    """Nodes (n,3) and tetrahedra (m,4, 0-based, in file order) of a gmsh MSH 2.2 ASCII file.

    Elements other than linear tetrahedra are ignored. Node ids are mapped to 0..n-1 in file order."""
    with open(path) as f:
        lines = f.read().splitlines()
    i = 0
    ids, X, tets = None, None, []
    while i < len(lines):
        s = lines[i].strip()
        if s == "$MeshFormat":
            ver = lines[i + 1].split()
            if not ver[0].startswith("2") or ver[1] != "0":
                raise ValueError("%s: need MSH 2.x ASCII, got %s" % (path, lines[i + 1]))
        elif s == "$Nodes":
            n = int(lines[i + 1])
            block = np.loadtxt(io.StringIO("\n".join(lines[i + 2:i + 2 + n])), ndmin=2)
            ids = block[:, 0].astype(np.int64)
            X = block[:, 1:4].copy()
            i += 2 + n
            continue
        elif s == "$Elements":
            n = int(lines[i + 1])
            for line in lines[i + 2:i + 2 + n]:
                p = line.split()
                if int(p[1]) == MSH_TET:
                    nt = int(p[2])
                    tets.append([int(v) for v in p[3 + nt:3 + nt + 4]])
            i += 2 + n
            continue
        i += 1
    if ids is None:
        raise ValueError("%s: no $Nodes section" % path)
    lookup = np.full(ids.max() + 1, -1, dtype=np.int64)
    lookup[ids] = np.arange(len(ids))
    T = lookup[np.array(tets, dtype=np.int64).reshape(-1, 4)]
    if (T < 0).any():
        raise ValueError("%s: tetrahedron references an unknown node" % path)
    return X, T


def read_tetgen(prefix):
    """Nodes and tets of tetgen's PREFIX.node / PREFIX.ele (any index base)."""
    with open(prefix + ".node") as f:
        head = f.readline().split()
        n = int(head[0])
        node = np.loadtxt(f, max_rows=n, ndmin=2, comments="#")
    with open(prefix + ".ele") as f:
        head = f.readline().split()
        m, npe = int(head[0]), int(head[1])
        if npe != 4:
            raise ValueError("tetgen .ele with %d nodes per element (expected 4)" % npe)
        ele = np.loadtxt(f, max_rows=m, ndmin=2, comments="#", dtype=np.int64)
    base = int(node[:, 0].min())
    X = np.zeros((int(node[:, 0].max()) - base + 1, 3))
    X[node[:, 0].astype(np.int64) - base] = node[:, 1:4]
    return X, ele[:, 1:5] - base


# --------------------------------------------------------------------------------------------------
# Writers


def _fmt_coords(X):
    # %.17g round-trips a double exactly, so written coordinates are the computed ones, byte-stable
    return ["%.17g %.17g %.17g" % (x, y, z) for x, y, z in X]


def write_surface_msh22(path, V, F):
    """A triangle surface as MSH 2.2 (one elementary surface 1, no physical groups)."""
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$Nodes", str(len(V))]
    out += ["%d %s" % (i + 1, c) for i, c in enumerate(_fmt_coords(V))]
    out += ["$EndNodes", "$Elements", str(len(F))]
    out += ["%d 2 2 1 1 %d %d %d" % (i + 1, a + 1, b + 1, c + 1) for i, (a, b, c) in enumerate(F)]
    out += ["$EndElements", ""]
    with open(path, "w") as f:
        f.write("\n".join(out))


def write_cell_vectors(path, A, comment_lines=()):
    """Per-cell vector side file: '#' comments, then N, then N lines 'ax ay az' (cell = tet order in the .msh)."""
    A = np.asarray(A, dtype=float)
    out = ["# " + c for c in comment_lines]
    out.append(str(len(A)))
    out += ["%.17g %.17g %.17g" % tuple(a) for a in A]
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


# --------------------------------------------------------------------------------------------------
# Geometry


def signed_volumes(X, T):
    a, b, c, d = (X[T[:, k]] for k in range(4))
    return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a)) / 6.0


def surface_volume(V, F):
    """Signed volume enclosed by a closed triangle surface (> 0 when its normals point outward)."""
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def check_closed_manifold(F, nverts):
    """Raise unless F is a closed, edge-manifold, consistently oriented surface; return (V-E+F, #edges)."""
    he = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    # each directed half-edge must appear once and its reverse once
    key = he[:, 0] * nverts + he[:, 1]
    if len(np.unique(key)) != len(key):
        raise ValueError("surface has a repeated directed edge (non-manifold or inconsistent orientation)")
    rkey = he[:, 1] * nverts + he[:, 0]
    if not np.isin(rkey, key).all():
        raise ValueError("surface has a boundary edge (not closed)")
    used = len(np.unique(F))
    E = len(he) // 2
    return used - E + len(F), E


def tet_quality(X, T):
    """Normalised quality 6*sqrt(2)*V / l_rms^3 in (0,1] (1 = regular tet), per tet."""
    e = [(0, 1), (0, 2), (0, 3), (1, 2), (1, 3), (2, 3)]
    l2 = sum(((X[T[:, i]] - X[T[:, j]]) ** 2).sum(1) for i, j in e) / 6.0
    return 6.0 * np.sqrt(2.0) * np.abs(signed_volumes(X, T)) / l2 ** 1.5


# --------------------------------------------------------------------------------------------------
# The mesh the solver reads


class TetMesh:
    """Tetrahedral mesh + physical groups, written as gmsh MSH 2.2 ASCII.

    X (n,3) coordinates, T (m,4) 0-based tets. Physical groups:
      cell_tag (m,)               physical volume of every tet (-> PETSc "Cell Sets")
      face_sets  [(tag, tris)]    boundary triangles (k,3), physical surface tag (-> "Face Sets")
      vertex_sets [(tag, nodes)]  node indices written as point elements (-> "Vertex Sets")
      names {(dim, tag): name}    $PhysicalNames (dim 0 points, 2 surfaces, 3 volumes)
    """

    def __init__(self, X, T):
        self.X = np.ascontiguousarray(X, dtype=float)
        self.T = np.ascontiguousarray(T, dtype=np.int64)
        self.cell_tag = np.ones(len(self.T), dtype=np.int64)
        self.face_sets = []
        self.vertex_sets = []
        self.names = {(3, 1): "body"}
        self.flipped = 0

    # -- cleaning -------------------------------------------------------------------------------
    def drop_unused_nodes(self):
        """Remove nodes no tet uses (gmsh geometry points, tetgen leftovers); keeps node order."""
        used = np.zeros(len(self.X), dtype=bool)
        used[self.T.ravel()] = True
        if used.all():
            return 0
        new = np.cumsum(used) - 1
        self.X = self.X[used]
        self.T = new[self.T]
        return int((~used).sum())

    def orient(self, rel_tol=1e-12):
        """Make every tet positively oriented (swap its last two nodes); raise on (near-)degenerate tets."""
        vol = signed_volumes(self.X, self.T)
        scale = np.ptp(self.X, axis=0).max() ** 3
        bad = np.abs(vol) <= rel_tol * scale
        if bad.any():
            raise ValueError("%d degenerate tetrahedra (|V| <= %g)" % (bad.sum(), rel_tol * scale))
        neg = vol < 0
        self.T[neg] = self.T[neg][:, [0, 1, 3, 2]]
        self.flipped = int(neg.sum())
        return self.flipped

    # -- boundary -------------------------------------------------------------------------------
    def boundary_faces(self):
        """Boundary triangles (faces of exactly one tet), outward oriented, in tet order.

        Returns (tris (k,3), owner tet index (k,))."""
        T = self.T
        # faces opposite node 3,2,1,0 with outward orientation for a positively oriented tet
        loc = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
        F = T[:, loc].reshape(-1, 3)
        owner = np.repeat(np.arange(len(T)), 4)
        S = np.sort(F, axis=1)
        n = len(self.X)
        if n < 2 ** 21:  # pack the sorted triple into one int64: much faster than unique(axis=0)
            key = (S[:, 0] * n + S[:, 1]) * n + S[:, 2]
            _, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
        else:
            _, inv, cnt = np.unique(S, axis=0, return_inverse=True, return_counts=True)
        once = cnt[inv.ravel()] == 1
        return F[once], owner[once]

    # -- physical groups --------------------------------------------------------------------------
    def add_face_set(self, tag, name, tris):
        self.face_sets.append((int(tag), np.asarray(tris, dtype=np.int64).reshape(-1, 3)))
        self.names[(2, int(tag))] = name

    def add_vertex_set(self, tag, name, nodes):
        self.vertex_sets.append((int(tag), np.unique(np.asarray(nodes, dtype=np.int64))))
        self.names[(0, int(tag))] = name

    def set_region(self, tag, name, mask):
        self.cell_tag[np.asarray(mask, dtype=bool)] = int(tag)
        self.names[(3, int(tag))] = name

    # -- output -----------------------------------------------------------------------------------
    def write_msh22(self, path):
        """gmsh MSH 2.2 ASCII: physical names, nodes, then point, triangle, tetrahedron elements.

        Each element carries 2 tags (physical, elementary), both = the physical tag. The tets are
        the last block, in self.T order, so PETSc cell k (serial) is self.T[k]."""
        if (signed_volumes(self.X, self.T) <= 0).any():
            raise ValueError("write_msh22: orient() the mesh first (non-positive tets)")
        out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(self.names))]
        for (dim, tag) in sorted(self.names):
            out.append('%d %d "%s"' % (dim, tag, self.names[(dim, tag)]))
        out += ["$EndPhysicalNames", "$Nodes", str(len(self.X))]
        out += ["%d %s" % (i + 1, c) for i, c in enumerate(_fmt_coords(self.X))]
        out.append("$EndNodes")
        nel = sum(len(v) for _, v in self.vertex_sets) + sum(len(f) for _, f in self.face_sets) + len(self.T)
        out += ["$Elements", str(nel)]
        k = 0
        for tag, nodes in self.vertex_sets:
            for v in nodes:
                k += 1
                out.append("%d 15 2 %d %d %d" % (k, tag, tag, v + 1))
        for tag, tris in self.face_sets:
            for a, b, c in tris:
                k += 1
                out.append("%d 2 2 %d %d %d %d %d" % (k, tag, tag, a + 1, b + 1, c + 1))
        for tag, (a, b, c, d) in zip(self.cell_tag, self.T):
            k += 1
            out.append("%d 4 2 %d %d %d %d %d %d" % (k, tag, tag, a + 1, b + 1, c + 1, d + 1))
        out += ["$EndElements", ""]
        with open(path, "w") as f:
            f.write("\n".join(out))

    def stats(self):
        """Counts and quality numbers, as a dict (printed in the build log and the README)."""
        vol = signed_volumes(self.X, self.T)
        q = tet_quality(self.X, self.T)
        s = {
            "tets": len(self.T),
            "vertices": len(self.X),
            "flipped_on_input": self.flipped,
            "volume": float(vol.sum()),
            "min_tet_volume": float(vol.min()),
            "min_quality": float(q.min()),
            "mean_quality": float(q.mean()),
            "bbox_min": [float(v) for v in self.X.min(0)],
            "bbox_max": [float(v) for v in self.X.max(0)],
        }
        for tag in sorted(set(self.cell_tag.tolist())):
            s["volume %d %s tets" % (tag, self.names[(3, tag)])] = int((self.cell_tag == tag).sum())
        for tag, tris in self.face_sets:
            s["surface %d %s triangles" % (tag, self.names[(2, tag)])] = len(tris)
        for tag, nodes in self.vertex_sets:
            s["point %d %s vertices" % (tag, self.names[(0, tag)])] = len(nodes)
        return s


def write_atomic(path, writer):
    """writer(tmp_path) then rename to path (same directory), so path is never half written."""
    tmp = "%s.tmp%d" % (path, os.getpid())
    try:
        writer(tmp)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
