"""Small, dependency-free (numpy only) mesh helpers for the aries mesh generators.

Everything here is deterministic: the same input arrays give the same output bytes.

Contents
- read_off / parse_off / read_tar_member : triangle surfaces in Geomview OFF format (optionally
  straight out of Debian's CGAL data.tar.gz, without unpacking it)
- write_surface_msh22 : a triangle surface as MSH 2.2 (input for gmsh's surface remeshing)
- read_msh22_tets / read_msh22_tris : the nodes and tetrahedra / triangles of a gmsh MSH 2.2 ASCII file
- read_tetgen : the .node/.ele output of tetgen (not used by the presets, which mesh with gmsh
  because tetgen keeps every input surface triangle; handy for ad-hoc meshes: tetgen -pq1.414 x.off)
- TetMesh : a tetrahedral mesh with cell regions, boundary face sets and vertex sets, that can
  orient its tets, drop unused nodes, extract its boundary and write the MSH 2.2 file the solver reads
- TriMesh : the same for triangle surface meshes in 3D (cells = triangles, face sets = edges): checks
  manifoldness / disk topology, orients consistently, finds the boundary loops
- write_msh22 : the MSH 2.2 writer both classes use (physical names, nodes, element blocks)
- write_cell_vectors : the per-cell side file format (fibers)
"""

import io
import os
import tarfile

import numpy as np

# gmsh MSH 2.2 element type numbers
MSH_POINT, MSH_LINE, MSH_TRI, MSH_TET = 15, 1, 2, 4
MSH_QUAD, MSH_HEX = 3, 5
MSH_TRI6, MSH_TET10 = 9, 11  # second order: the corners, then one node per edge
# gmsh's node order: node 4 + k of a 10-node tet on the edge TET10_EDGES[k], node 3 + k of a 6-node triangle on
# TRI6_EDGES[k]
TET10_EDGES = np.array([[0, 1], [1, 2], [0, 2], [0, 3], [2, 3], [1, 3]])
TRI6_EDGES = np.array([[0, 1], [1, 2], [2, 0]])


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


def read_msh22_elements(path, etype, npe):
    """Nodes (n,3) and the elements of gmsh type etype with npe nodes each ((m,npe), 0-based, in file
    order) of a gmsh MSH 2.2 ASCII file. Other elements are ignored. Node ids are mapped to 0..n-1
    in file order."""
    with open(path) as f:
        lines = f.read().splitlines()
    i = 0
    ids, X, cells = None, None, []
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
                if int(p[1]) == etype:
                    nt = int(p[2])
                    cells.append([int(v) for v in p[3 + nt:3 + nt + npe]])
            i += 2 + n
            continue
        i += 1
    if ids is None:
        raise ValueError("%s: no $Nodes section" % path)
    lookup = np.full(ids.max() + 1, -1, dtype=np.int64)
    lookup[ids] = np.arange(len(ids))
    T = lookup[np.array(cells, dtype=np.int64).reshape(-1, npe)]
    if (T < 0).any():
        raise ValueError("%s: element references an unknown node" % path)
    return X, T


def read_msh22_tets(path):
    """Nodes (n,3) and tetrahedra (m,4, 0-based, in file order) of a gmsh MSH 2.2 ASCII file."""
    return read_msh22_elements(path, MSH_TET, 4)


def read_msh22_tris(path):
    """Nodes (n,3) and triangles (m,3, 0-based, in file order) of a gmsh MSH 2.2 ASCII file."""
    return read_msh22_elements(path, MSH_TRI, 3)


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


def write_msh22(path, names, X, blocks):
    """The MSH 2.2 ASCII file the solver reads.

    names  {(dim, tag): name}             -> $PhysicalNames, sorted by (dim, tag)
    X      (n,3) node coordinates         -> $Nodes 1..n (%.17g)
    blocks [(etype, tags (k,), conn (k,npe) 0-based)] -> $Elements, numbered 1.. in block order; each
           element carries 2 tags (physical, elementary), both = its physical tag."""
    out = ["$MeshFormat", "2.2 0 8", "$EndMeshFormat", "$PhysicalNames", str(len(names))]
    for (dim, tag) in sorted(names):
        out.append('%d %d "%s"' % (dim, tag, names[(dim, tag)]))
    out += ["$EndPhysicalNames", "$Nodes", str(len(X))]
    out += ["%d %s" % (i + 1, c) for i, c in enumerate(_fmt_coords(X))]
    out.append("$EndNodes")
    out += ["$Elements", str(sum(len(conn) for _, _, conn in blocks))]
    k = 0
    for etype, tags, conn in blocks:
        conn = np.asarray(conn, dtype=np.int64)
        fmt = "%d " + str(int(etype)) + " 2 %d %d" + " %d" * conn.shape[1]
        for tag, nodes in zip(np.broadcast_to(np.asarray(tags, dtype=np.int64), (len(conn),)).tolist(),
                              (conn + 1).tolist()):
            k += 1
            out.append(fmt % (k, tag, tag, *nodes))
    out += ["$EndElements", ""]
    with open(path, "w") as f:
        f.write("\n".join(out))


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
        # second order (set_edge_nodes): sorted corner pairs (k,2) and the node on each edge (k,3)
        self.edges = None
        self.edge_X = None

    @classmethod
    def from_second_order(cls, X, T10):
        """A mesh of 10-node tets in gmsh's node order: the corners as the mesh, the edge nodes kept (curved
        where the generator placed them on the geometry)."""
        T10 = np.asarray(T10, dtype=np.int64)
        m = cls(X, T10[:, :4])
        E = np.sort(T10[:, TET10_EDGES].reshape(-1, 2), axis=1)
        mids = T10[:, 4:].reshape(-1)
        E, first = np.unique(E, axis=0, return_index=True)
        m.set_edge_nodes(E, np.asarray(X, dtype=float)[mids[first]])
        return m

    def set_edge_nodes(self, E, XE):
        """Make the mesh second order: XE[k] is the node on the edge joining corners E[k] (every edge of the tets
        must have one; written as 10-node tets and 6-node boundary triangles)."""
        E = np.sort(np.asarray(E, dtype=np.int64).reshape(-1, 2), axis=1)
        order = np.lexsort((E[:, 1], E[:, 0]))
        self.edges, self.edge_X = E[order], np.asarray(XE, dtype=float).reshape(-1, 3)[order]

    def edge_node_index(self, pairs):
        """The edge-node number (into self.edges) of each corner pair (..., 2)."""
        P = np.sort(np.asarray(pairs, dtype=np.int64), axis=-1)
        n = len(self.X)
        keys = self.edges[:, 0] * n + self.edges[:, 1]
        k = P[..., 0] * n + P[..., 1]
        at = np.searchsorted(keys, k)
        if (at >= len(keys)).any() or (keys[np.minimum(at, len(keys) - 1)] != k).any():
            raise ValueError("an edge of the mesh has no edge node")
        return at

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
        if self.edges is not None:
            self.set_edge_nodes(new[self.edges], self.edge_X)
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
    FACE_NODES = 3  # boundary triangles (HexMesh: quadrangles)

    def add_face_set(self, tag, name, tris):
        self.face_sets.append((int(tag), np.asarray(tris, dtype=np.int64).reshape(-1, self.FACE_NODES)))
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
        blocks = [(MSH_POINT, tag, nodes.reshape(-1, 1)) for tag, nodes in self.vertex_sets]
        if self.edges is None:
            blocks += [(MSH_TRI, tag, tris) for tag, tris in self.face_sets]
            blocks.append((MSH_TET, self.cell_tag, self.T))
            write_msh22(path, self.names, self.X, blocks)
            return
        # second order: the edge nodes numbered after the corners, so PETSc's vertices are the corners in order
        n = len(self.X)
        for tag, tris in self.face_sets:
            mids = n + self.edge_node_index(tris[:, TRI6_EDGES])
            blocks.append((MSH_TRI6, tag, np.c_[tris, mids]))
        mids = n + self.edge_node_index(self.T[:, TET10_EDGES])
        blocks.append((MSH_TET10, self.cell_tag, np.c_[self.T, mids]))
        write_msh22(path, self.names, np.r_[self.X, self.edge_X], blocks)

    def stats(self):
        """Counts and quality numbers, as a dict (printed in the build log and the README)."""
        vol = signed_volumes(self.X, self.T)
        q = tet_quality(self.X, self.T)
        s = {
            "tets": len(self.T),
            "vertices": len(self.X),
            "order": 1 if self.edges is None else 2,
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


# --------------------------------------------------------------------------------------------------
# Triangle surface meshes


def triangle_quality(X, T):
    """Normalised quality 4*sqrt(3)*A / (sum of squared edge lengths) in (0,1] (1 = equilateral)."""
    a, b, c = X[T[:, 0]], X[T[:, 1]], X[T[:, 2]]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    l2 = ((b - a) ** 2).sum(1) + ((c - b) ** 2).sum(1) + ((a - c) ** 2).sum(1)
    return 4.0 * np.sqrt(3.0) * area / l2


def _components(n, pairs):
    """Connected-component label (the smallest member) of each of n items joined by pairs (k,2)."""
    lab = np.arange(n)
    pairs = np.asarray(pairs, dtype=np.int64).reshape(-1, 2)
    while True:
        m = np.minimum(lab[pairs[:, 0]], lab[pairs[:, 1]])
        new = lab.copy()
        np.minimum.at(new, pairs[:, 0], m)
        np.minimum.at(new, pairs[:, 1], m)
        while True:  # pointer jumping: label of the label
            nxt = new[new]
            if (nxt == new).all():
                break
            new = nxt
        if (new == lab).all():
            return lab
        lab = new


class TriMesh:
    """Triangle surface mesh (nodes in 3D) + physical groups, written as gmsh MSH 2.2 ASCII.

    X (n,3) coordinates, T (m,3) 0-based triangles. Physical groups:
      cell_tag (m,)                physical surface of every triangle (-> PETSc "Cell Sets")
      edge_sets [(tag, edges)]     edges (k,2) written as line elements, physical curve tag
                                   (-> "Face Sets": in a 2D mesh the faces are edges)
      vertex_sets [(tag, nodes)]   node indices written as point elements (-> "Vertex Sets")
      names {(dim, tag): name}     $PhysicalNames (dim 0 points, 1 curves, 2 surfaces)
    Half-edges of triangle k are (T[k,0],T[k,1]), (T[k,1],T[k,2]), (T[k,2],T[k,0]); the normal is
    (x1-x0) x (x2-x0). A consistently oriented surface uses every interior edge once in each direction.
    """

    def __init__(self, X, T, name="surface"):
        self.X = np.ascontiguousarray(X, dtype=float)
        self.T = np.ascontiguousarray(T, dtype=np.int64)
        self.cell_tag = np.ones(len(self.T), dtype=np.int64)
        self.edge_sets = []
        self.vertex_sets = []
        self.names = {(2, 1): name}
        self.flipped = 0

    # -- geometry ---------------------------------------------------------------------------------
    def area_vectors(self):
        """(m,3): normal * area of every triangle."""
        a, b, c = (self.X[self.T[:, k]] for k in range(3))
        return 0.5 * np.cross(b - a, c - a)

    def areas(self):
        return np.linalg.norm(self.area_vectors(), axis=1)

    # -- cleaning ---------------------------------------------------------------------------------
    def drop_unused_nodes(self):
        """Remove nodes no triangle uses; keeps node order. Returns how many were dropped."""
        used = np.zeros(len(self.X), dtype=bool)
        used[self.T.ravel()] = True
        if used.all():
            return 0
        new = np.cumsum(used) - 1
        self.X = self.X[used]
        self.T = new[self.T]
        if self.edges is not None:
            self.set_edge_nodes(new[self.edges], self.edge_X)
        return int((~used).sum())

    def drop_bad_triangles(self):
        """Remove triangles with a repeated node and repeated triangles (same node set; the first is
        kept). Returns (#degenerate, #duplicates) removed. Geometric degeneracy is checked on write."""
        T = self.T
        degen = (T[:, 0] == T[:, 1]) | (T[:, 1] == T[:, 2]) | (T[:, 2] == T[:, 0])
        S = np.sort(T, axis=1)
        _, first = np.unique(S, axis=0, return_index=True)
        keep = np.zeros(len(T), dtype=bool)
        keep[first] = True
        dup = ~keep & ~degen
        keep &= ~degen
        self.T = T[keep]
        self.cell_tag = self.cell_tag[keep]
        return int(degen.sum()), int(dup.sum())

    # -- topology ---------------------------------------------------------------------------------
    def half_edges(self):
        """(3m,2) directed edges, triangle-major: triangle k's edges are rows 3k, 3k+1, 3k+2."""
        return self.T[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2)

    def _edge_index(self):
        """Undirected edge id of every half-edge (3m,), and the number of triangles per edge."""
        he = self.half_edges()
        n = len(self.X)
        key = np.minimum(he[:, 0], he[:, 1]) * n + np.maximum(he[:, 0], he[:, 1])
        _, eid, cnt = np.unique(key, return_inverse=True, return_counts=True)
        return eid.ravel(), cnt

    def topology(self):
        """Manifoldness, orientation and topology numbers, as a dict (raises nothing)."""
        he = self.half_edges()
        eid, cnt = self._edge_index()
        n, m = len(self.X), len(self.T)
        used = np.zeros(n, dtype=bool)
        used[self.T.ravel()] = True
        nonmanifold_edges = int((cnt > 2).sum())
        # orientation: each interior edge's two half-edges must be opposite
        dkey = he[:, 0] * n + he[:, 1]
        repeated_directed = len(dkey) - len(np.unique(dkey))
        # fans around vertices: corners (triangle, local vertex) are joined across interior edges
        order = np.argsort(eid, kind="stable")
        es = eid[order]
        pair = np.flatnonzero(es[:-1] == es[1:])  # both half-edges of an edge with 2 triangles
        pair = pair[cnt[es[pair]] == 2]
        h1, h2 = order[pair], order[pair + 1]
        corner = lambda h, end: 3 * (h // 3) + (h % 3 + end) % 3  # corner at the source/target of h
        same = (he[h1, 0] == he[h2, 0])  # same direction (inconsistent) or opposite
        j = [np.c_[corner(h1, 0), np.where(same, corner(h2, 0), corner(h2, 1))],
             np.c_[corner(h1, 1), np.where(same, corner(h2, 1), corner(h2, 0))]]
        clab = _components(3 * m, np.concatenate(j))
        cv = self.T.ravel()
        fans = np.bincount(cv[np.unique(clab)], minlength=n)
        nonmanifold_vertices = int((fans[used] > 1).sum())
        tri_lab = _components(m, np.c_[h1 // 3, h2 // 3])
        # boundary loops, counted without using orientation: components of the boundary edge graph
        B = he[cnt[eid] == 1]
        blab = _components(n, B)[B[:, 0]]
        loop_lengths = sorted(np.unique(blab, return_counts=True)[1].tolist(), reverse=True)
        return {
            "vertices": int(used.sum()),
            "unused_vertices": int((~used).sum()),
            "triangles": m,
            "edges": len(cnt),
            "boundary_edges": int((cnt == 1).sum()),
            "nonmanifold_edges": nonmanifold_edges,
            "nonmanifold_vertices": nonmanifold_vertices,
            "consistently_oriented": repeated_directed == 0 and nonmanifold_edges == 0,
            "components": int(len(np.unique(tri_lab))),
            "euler_characteristic": int(used.sum()) - len(cnt) + m,
            "boundary_loops": len(loop_lengths),
            "boundary_loop_lengths": loop_lengths,
        }

    def check_disk(self, what="surface"):
        """Raise unless the mesh is a connected, manifold, consistently oriented topological disk
        (Euler characteristic 1, exactly one boundary loop). Returns topology()."""
        t = self.topology()
        problems = []
        if t["unused_vertices"]:
            problems.append("%d unused vertices" % t["unused_vertices"])
        if t["nonmanifold_edges"] or t["nonmanifold_vertices"]:
            problems.append("%d non-manifold edges, %d non-manifold vertices"
                            % (t["nonmanifold_edges"], t["nonmanifold_vertices"]))
        if not t["consistently_oriented"]:
            problems.append("not consistently oriented")
        if t["components"] != 1:
            problems.append("%d connected components" % t["components"])
        if t["euler_characteristic"] != 1 or t["boundary_loops"] != 1:
            problems.append("Euler characteristic %d with %d boundary loops (a disk has 1 and 1)"
                            % (t["euler_characteristic"], t["boundary_loops"]))
        if problems:
            raise ValueError("%s is not a manifold disk: %s" % (what, "; ".join(problems)))
        return t

    def orient_consistently(self):
        """Flip triangles so that every interior edge is used once in each direction (breadth-first
        from triangle 0 of each component, which keeps its orientation). Raises on non-manifold edges
        or a non-orientable surface. Returns the number of triangles flipped."""
        he = self.half_edges()
        eid, cnt = self._edge_index()
        if (cnt > 2).any():
            raise ValueError("%d non-manifold edges (more than 2 triangles)" % (cnt > 2).sum())
        order = np.argsort(eid, kind="stable")
        es = eid[order]
        pair = np.flatnonzero(es[:-1] == es[1:])
        h1, h2 = order[pair], order[pair + 1]
        t1, t2 = h1 // 3, h2 // 3
        same = (he[h1, 0] == he[h2, 0]).astype(np.int8)  # 1: the two triangles disagree
        m = len(self.T)
        # adjacency lists (CSR)
        a = np.concatenate([t1, t2])
        b = np.concatenate([t2, t1])
        s = np.concatenate([same, same])
        o = np.argsort(a, kind="stable")
        a, b, s = a[o], b[o], s[o]
        ptr = np.searchsorted(a, np.arange(m + 1))
        flip = np.full(m, -1, dtype=np.int8)
        nbr, par = b.tolist(), s.tolist()
        ptr = ptr.tolist()
        for root in range(m):
            if flip[root] >= 0:
                continue
            flip[root] = 0
            queue = [root]
            for t in queue:
                ft = flip[t]
                for q in range(ptr[t], ptr[t + 1]):
                    u, want = nbr[q], ft ^ par[q]
                    if flip[u] < 0:
                        flip[u] = want
                        queue.append(u)
                    elif flip[u] != want:
                        raise ValueError("surface is not orientable")
        f = flip == 1
        self.T[f] = self.T[f][:, [0, 2, 1]]
        self.flipped += int(f.sum())
        return int(f.sum())

    def flip_all(self):
        self.T = self.T[:, [0, 2, 1]].copy()
        self.flipped = len(self.T) - self.flipped

    def orient_up(self, up=(0.0, 0.0, 1.0)):
        """After orient_consistently(): flip everything if the total area vector points against up."""
        if float(self.area_vectors().sum(0) @ np.asarray(up, dtype=float)) < 0:
            self.flip_all()
            return True
        return False

    def capped_volume(self):
        """Signed volume enclosed by the surface closed by a fan from the centroid of each boundary
        loop (> 0 when the normals point out of the closed-up shape)."""
        vol = surface_volume(self.X, self.T)
        for loop in self.boundary_loops():
            c = self.X[loop[:, 0]].mean(0)
            u, w = self.X[loop[:, 0]], self.X[loop[:, 1]]  # loop edge u -> w; cap triangle (c, w, u)
            vol += float((np.cross(w, u) @ c).sum() / 6.0)
        return vol

    def orient_outward(self):
        """After orient_consistently(): flip everything unless the normals point out of the capped
        surface (capped_volume() > 0)."""
        if self.capped_volume() < 0:
            self.flip_all()
            return True
        return False

    def boundary_edges(self):
        """Boundary half-edges (edges of exactly one triangle), directed as in their triangle (the
        surface lies to the left, seen from the normal side), in triangle order. Returns (k,2)."""
        eid, cnt = self._edge_index()
        return self.half_edges()[cnt[eid] == 1]

    def boundary_loops(self):
        """The boundary as closed loops of directed boundary edges, each a (k,2) array in walking
        order. Loops are sorted by their smallest vertex and start at the edge leaving it.
        Requires a vertex-manifold surface (one outgoing boundary edge per boundary vertex)."""
        B = self.boundary_edges()
        if len(B) == 0:
            return []
        nxt = {}
        for u, w in B.tolist():
            if u in nxt:
                raise ValueError("vertex %d has two outgoing boundary edges (non-manifold)" % u)
            nxt[u] = w
        loops, seen = [], set()
        for s in sorted(nxt):
            if s in seen:
                continue
            loop, u = [], s
            while u not in seen:
                seen.add(u)
                loop.append((u, nxt[u]))
                u = nxt[u]
                if u not in nxt:
                    raise ValueError("open boundary chain at vertex %d" % u)
            if u != s:
                raise ValueError("boundary loops cross at vertex %d" % u)
            loops.append(np.array(loop, dtype=np.int64))
        return loops

    # -- physical groups --------------------------------------------------------------------------
    def add_edge_set(self, tag, name, edges):
        self.edge_sets.append((int(tag), np.asarray(edges, dtype=np.int64).reshape(-1, 2)))
        self.names[(1, int(tag))] = name

    def add_vertex_set(self, tag, name, nodes):
        self.vertex_sets.append((int(tag), np.unique(np.asarray(nodes, dtype=np.int64))))
        self.names[(0, int(tag))] = name

    def set_region(self, tag, name, mask):
        self.cell_tag[np.asarray(mask, dtype=bool)] = int(tag)
        self.names[(2, int(tag))] = name

    # -- output -----------------------------------------------------------------------------------
    def write_msh22(self, path, rel_tol=1e-12):
        """gmsh MSH 2.2 ASCII: physical names, nodes, then point, line, triangle elements.

        Each element carries 2 tags (physical, elementary), both = the physical tag. The triangles
        are the last block, in self.T order, so PETSc cell k (serial) is self.T[k]."""
        A = self.areas()
        scale = np.ptp(self.X, axis=0).max() ** 2
        if (A <= rel_tol * scale).any():
            raise ValueError("%d degenerate triangles" % (A <= rel_tol * scale).sum())
        he = self.half_edges()
        key = he[:, 0] * len(self.X) + he[:, 1]
        if len(np.unique(key)) != len(key):
            raise ValueError("write_msh22: triangles are not consistently oriented (orient_consistently())")
        blocks = [(MSH_POINT, tag, nodes.reshape(-1, 1)) for tag, nodes in self.vertex_sets]
        blocks += [(MSH_LINE, tag, edges) for tag, edges in self.edge_sets]
        blocks.append((MSH_TRI, self.cell_tag, self.T))
        write_msh22(path, self.names, self.X, blocks)

    def stats(self):
        """Counts, topology and quality numbers, as a dict (build log, .json, README)."""
        t = self.topology()
        A = self.areas()
        q = triangle_quality(self.X, self.T)
        s = {
            "triangles": len(self.T),
            "vertices": len(self.X),
            "edges": t["edges"],
            "boundary_edges": t["boundary_edges"],
            "boundary_loops": t["boundary_loops"],
            "boundary_loop_lengths": t["boundary_loop_lengths"],
            "euler_characteristic": t["euler_characteristic"],
            "components": t["components"],
            "flipped_on_input": self.flipped,
            "area": float(A.sum()),
            "min_triangle_area": float(A.min()),
            "min_quality": float(q.min()),
            "mean_quality": float(q.mean()),
            "bbox_min": [float(v) for v in self.X.min(0)],
            "bbox_max": [float(v) for v in self.X.max(0)],
        }
        for tag in sorted(set(self.cell_tag.tolist())):
            s["surface %d %s triangles" % (tag, self.names[(2, tag)])] = int((self.cell_tag == tag).sum())
        for tag, edges in self.edge_sets:
            s["curve %d %s edges" % (tag, self.names[(1, tag)])] = len(edges)
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


# --------------------------------------------------------------------------------------------------
# Hexahedral meshes


# The 6 faces of a hexahedron in gmsh node order (bottom 0-3 counterclockwise seen from above, top 4-7), each
# counterclockwise seen from outside.
HEX_FACES = np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [2, 3, 7, 6], [1, 2, 6, 5], [0, 4, 7, 3]])


def hex_jacobians(X, H):
    """det J of each hexahedron's trilinear map at its 8 corners ((m, 8)); all > 0 for a valid, positively numbered
    cell."""
    P = X[H]  # (m, 8, 3)
    nbr = [(1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3)]
    return np.stack([np.einsum("ij,ij->i", P[:, a] - P[:, v], np.cross(P[:, b] - P[:, v], P[:, c] - P[:, v]))
                     for v, (a, b, c) in enumerate(nbr)], axis=1)


class HexMesh(TetMesh):
    """Trilinear hexahedral mesh + physical groups, written as gmsh MSH 2.2 ASCII (hexahedra: element type 5, gmsh
    node order; boundary groups: quadrangles, type 3). TetMesh's members, with self.T (m,8) the hexahedra and the face
    sets quadrangles (k,4); drop_unused_nodes before adding groups (it renumbers the nodes)."""

    FACE_NODES = 4

    def boundary_faces(self):
        """Boundary quadrangles (k,4), outward, and the hexahedron of each."""
        F = self.T[:, HEX_FACES].reshape(-1, 4)
        key = np.sort(F, axis=1)
        _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
        once = cnt[inv.ravel()] == 1
        return F[once], np.repeat(np.arange(len(self.T)), 6)[once]

    def write_msh22(self, path):
        if (hex_jacobians(self.X, self.T) <= 0).any():
            raise ValueError("write_msh22: a hexahedron with det J <= 0 at a corner")
        blocks = [(MSH_POINT, tag, nodes.reshape(-1, 1)) for tag, nodes in self.vertex_sets]
        blocks += [(MSH_QUAD, tag, quads) for tag, quads in self.face_sets]
        blocks.append((MSH_HEX, self.cell_tag, self.T))
        write_msh22(path, self.names, self.X, blocks)

    def stats(self):
        J = hex_jacobians(self.X, self.T)
        P = self.X[self.T]
        s = {
            "hexes": len(self.T),
            "vertices": len(self.X),
            "flipped_on_input": 0,
            "min_corner_jacobian": float(J.min()),
            "max_corner_jacobian": float(J.max()),
            "bbox_min": [float(v) for v in self.X.min(0)],
            "bbox_max": [float(v) for v in self.X.max(0)],
            "mean_cell_size": float(np.abs(P.max(1) - P.min(1)).mean()),
        }
        for tag, quads in self.face_sets:
            s["surface %d %s quadrangles" % (tag, self.names[(2, tag)])] = len(quads)
        for tag, nodes in self.vertex_sets:
            s["point %d %s vertices" % (tag, self.names[(0, tag)])] = len(nodes)
        return s


def grid_hexes(mask):
    """Hexahedra of the cells of a boolean voxel grid mask (nx, ny, nz) on the node grid (nx+1, ny+1, nz+1), node id
    i + (nx+1) (j + (ny+1) k), in gmsh node order; cell-major (x fastest)."""
    nx, ny, nz = mask.shape
    k, j, i = np.nonzero(mask.transpose(2, 1, 0))
    node = lambda a, b, c: a + (nx + 1) * (b + (ny + 1) * c)
    return np.stack([node(i, j, k), node(i + 1, j, k), node(i + 1, j + 1, k), node(i, j + 1, k),
                     node(i, j, k + 1), node(i + 1, j, k + 1), node(i + 1, j + 1, k + 1), node(i, j + 1, k + 1)],
                    axis=1)


def inside_closed_surface_columns(V, F, xs, ys, zs):
    """Boolean (len(xs), len(ys), len(zs)): whether each grid point lies inside the closed triangle surface (V, F),
    by the parity of the surface's crossings of the vertical line through (x, y) below z."""
    inside = np.zeros((len(xs), len(ys), len(zs)), dtype=bool)
    crossings = [[[] for _ in ys] for _ in xs]
    a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
    for t in range(len(F)):
        lo = np.minimum(np.minimum(a[t], b[t]), c[t])
        hi = np.maximum(np.maximum(a[t], b[t]), c[t])
        ii = np.nonzero((xs >= lo[0]) & (xs < hi[0]))[0]
        jj = np.nonzero((ys >= lo[1]) & (ys < hi[1]))[0]
        if len(ii) == 0 or len(jj) == 0:
            continue
        px, py = np.meshgrid(xs[ii], ys[jj], indexing="ij")
        d = (b[t, 0] - a[t, 0]) * (c[t, 1] - a[t, 1]) - (c[t, 0] - a[t, 0]) * (b[t, 1] - a[t, 1])
        if d == 0:
            continue
        l1 = ((px - a[t, 0]) * (c[t, 1] - a[t, 1]) - (c[t, 0] - a[t, 0]) * (py - a[t, 1])) / d
        l2 = ((b[t, 0] - a[t, 0]) * (py - a[t, 1]) - (px - a[t, 0]) * (b[t, 1] - a[t, 1])) / d
        l0 = 1 - l1 - l2
        hit = (l0 >= 0) & (l1 >= 0) & (l2 >= 0)
        z = l0 * a[t, 2] + l1 * b[t, 2] + l2 * c[t, 2]
        for p, q in zip(*np.nonzero(hit)):
            crossings[ii[p]][jj[q]].append(z[p, q])
    for p in range(len(xs)):
        for q in range(len(ys)):
            zc = np.sort(np.array(crossings[p][q]))
            if len(zc):
                inside[p, q] = (np.searchsorted(zc, zs) % 2) == 1
    return inside
