"""End-to-end cases: trilinear hexahedra and quadratic tetrahedra (-element p2) against exact solutions, with their
XDMF output."""
import math

import numpy as np

from harness import fail
from .common import ARGS, mesh, meta_box, out_base, read_state, run


def hex_corner_jacobians(points, cells):
    """det J at the 8 corners of each hexahedron given in VTK order (as XDMF and meshio store them)."""
    P = points[cells]
    nbr = [(1, 3, 4), (2, 0, 5), (3, 1, 6), (0, 2, 7), (7, 5, 0), (4, 6, 1), (5, 7, 2), (6, 4, 3)]
    return np.stack([np.einsum("ij,ij->i", P[:, a] - P[:, v], np.cross(P[:, b] - P[:, v], P[:, c] - P[:, v]))
                     for v, (a, b, c) in enumerate(nbr)], axis=1)


def case_hex_elements():
    """Trilinear hexahedra (Q1, 2x2x2 Gauss points) end to end, on the 6^3 cube (meshes/generate.sh hexcube test):
    (1) the hanging bar (iarap, nu = 0, rho g = 5000, top clamped): the exact u_z = -rho g (1 - z^2) / (2 E) is
    quadratic along the bar and the grid is uniform, so Q1 with the lumped (row-sum) gravity is exact at the nodes
    (the 1D superconvergence of linear elements), up to the solver's tolerance: <= 1e-9 L; (2) a dead traction on the
    top quadrangles (-load_traction_top 2000, bottom clamped, iarap nu = 0): F = diag(1, 1, 1.2) exactly, so every
    vertex is at z (1.2): <= 1e-9 L (checks the quadrangle's vertex shares); (3) the XDMF output names a Hexahedron
    topology that meshio reads with every cell positively oriented in VTK order, and per-cell fields per hexahedron;
    (4) -psd_scope element (the whole 24x24 element Hessian filtered) ends where the per-point filter does."""
    import meshio
    msh = mesh("hexcube")
    L = math.sqrt(3.0)
    tag = "hex_hanging_np%d" % ARGS.ranks
    run(["-dm_plex_filename", msh, "-energy", "iarap", "-E", "1e4", "-nu", "0", "-bc_clamp", "top", "-density", "1000",
         "-gravity", "0,0,-5", "-steps", "1", "-newton_tol", "1e-10", "-output", out_base(tag), "-output_fields",
         "alpha,von_mises", "-stats", out_base(tag) + ".csv"], tag=tag)
    rest, _, x, _ = read_state(out_base(tag))
    exact = rest.copy()
    exact[:, 2] += -5000.0 * (1.0 - rest[:, 2] ** 2) / 2e4
    err = np.abs(x - exact).max() / L
    print("hanging bar on hexahedra: max nodal error %.2e L (limit 1e-9)" % err)
    if not err <= 1e-9:
        fail("hanging bar on hexahedra: nodal error %.2e L" % err)
    with meshio.xdmf.TimeSeriesReader(out_base(tag) + ".xmf") as r:
        points, cells = r.read_points_cells()
        _, _, cell_data = r.read_data(r.num_steps - 1)
    if [c.type for c in cells] != ["hexahedron"] or len(cells[0].data) != 216:
        fail("XDMF cells %s, expected 216 hexahedra" % [(c.type, len(c.data)) for c in cells])
    if any(len(v[0]) != 216 for v in cell_data.values()) or "von_mises" not in cell_data:
        fail("XDMF cell fields %s, expected one value per hexahedron" % {k: len(v[0]) for k, v in cell_data.items()})
    jac = hex_corner_jacobians(np.asarray(points), np.asarray(cells[0].data))
    print("XDMF: %d hexahedra, corner det J in [%.3g, %.3g] (VTK order)" % (len(jac), jac.min(), jac.max()))
    if not (jac > 0).all():
        fail("hexahedra in the XDMF are not in VTK order: corner det J down to %.3g" % jac.min())
    with open(out_base(tag) + ".xmf") as fh:
        if 'TopologyType="Hexahedron"' not in fh.read():
            fail("the XDMF does not name a Hexahedron topology")
    # The whole-element filter (-psd_scope element: the 24x24 element Hessian projected) reaches the same solution.
    tag = "hex_hanging_element_filter_np%d" % ARGS.ranks
    run(["-dm_plex_filename", msh, "-energy", "fiber", "-E", "1e4", "-nu", "0", "-gamma", "2000", "-fiber", "1,1,1",
         "-bc_clamp", "top", "-density", "1000", "-gravity", "0,0,-5", "-steps", "1", "-newton_tol", "1e-10",
         "-psd_scope", "element", "-output", out_base(tag)], tag=tag)
    run(["-dm_plex_filename", msh, "-energy", "fiber", "-E", "1e4", "-nu", "0", "-gamma", "2000", "-fiber", "1,1,1",
         "-bc_clamp", "top", "-density", "1000", "-gravity", "0,0,-5", "-steps", "1", "-newton_tol", "1e-10",
         "-output", out_base(tag + "_point")], tag=tag + "_point")
    diff = np.abs(read_state(out_base(tag))[2] - read_state(out_base(tag + "_point"))[2]).max() / L
    print("fiber (1,1,1) hanging: -psd_scope element vs point: %.2e L (limit 1e-9)" % diff)
    if not diff <= 1e-9:
        fail("-psd_scope element and point end %.2e L apart" % diff)
    tag = "hex_traction_np%d" % ARGS.ranks
    run(["-dm_plex_filename", msh, "-energy", "iarap", "-E", "1e4", "-nu", "0", "-bc_clamp", "bottom",
         "-load_traction_top", "0,0,2000", "-steps", "2", "-newton_tol", "1e-10", "-output", out_base(tag),
         "-stats", out_base(tag) + ".csv"], tag=tag)
    rest, _, x, _ = read_state(out_base(tag))
    exact = rest.copy()
    exact[:, 2] *= 1.2
    err = np.abs(x - exact).max() / L
    print("dead traction on the top quadrangles: max error %.2e L (limit 1e-9)" % err)
    if not err <= 1e-9:
        fail("traction on hexahedra: error %.2e L" % err)


def case_p2_elements():
    """Quadratic tetrahedra (-element p2: 10 nodes, 4 points) end to end on the unit cube (meshes/generate.sh cube
    test, 6^3 x 6 tets: 2,197 nodes): (1) the hanging bar (iarap, nu = 0, top clamped, rho g = 5000): the exact
    u_z = -rho g (1 - z^2) / (2 E) is quadratic, so P2 with gravity's consistent load holds it exactly at every node,
    edge nodes too, up to the solver's tolerance: <= 1e-9 L (P1 on the same mesh: 6.5e-3 L); (2) a dead traction on
    the top triangles (bottom clamped): F = diag(1, 1, 1.2) exactly, <= 1e-9 L (checks the face's load shares: 0 at
    corners, A/3 at edge nodes); (3) the XDMF output names a Tetrahedron_10 topology that meshio reads as tetra10, one
    node per vertex and edge, every element positively oriented with its edge nodes at the middles of its edges (VTK's
    node order), and one cell value per element. (A cylinder would not do: its faceted side makes the cross-section
    vary along the axis, so the uniaxial solutions are not exact there.)"""
    import meshio
    msh = mesh("cube")
    lo, hi = [np.array(v) for v in meta_box(msh)]
    L = np.linalg.norm(hi - lo)
    zb, zt = lo[2], hi[2]
    tag = "p2_hanging_np%d" % ARGS.ranks
    run(["-dm_plex_filename", msh, "-element", "p2", "-energy", "iarap", "-E", "1e4", "-nu", "0", "-bc_clamp", "top",
         "-density", "1000", "-gravity", "0,0,-5", "-steps", "1", "-newton_tol", "1e-10", "-output", out_base(tag),
         "-output_fields", "alpha,von_mises", "-stats", out_base(tag) + ".csv"], tag=tag)
    rest, _, x, _ = read_state(out_base(tag))
    exact = rest.copy()
    exact[:, 2] += -5000.0 * ((zt - zb) ** 2 - (rest[:, 2] - zb) ** 2) / 2e4
    err = np.abs(x - exact).max() / L
    moved = np.abs(exact - rest).max() / L
    print("hanging bar on P2: max nodal error %.2e L (limit 1e-9; the bottom moves %.2e L)" % (err, moved))
    if not err <= 1e-9:
        fail("hanging bar on P2: nodal error %.2e L" % err)
    with meshio.xdmf.TimeSeriesReader(out_base(tag) + ".xmf") as r:
        points, cells = r.read_points_cells()
        _, _, cell_data = r.read_data(r.num_steps - 1)
    with open(out_base(tag) + ".xmf") as fh:
        if 'TopologyType="Tetrahedron_10"' not in fh.read():
            fail("the XDMF does not name a Tetrahedron_10 topology")
    if [c.type for c in cells] != ["tetra10"] or len(points) != 13 ** 3:
        fail("XDMF cells %s on %d nodes, expected tetra10 on 13^3" % ([c.type for c in cells], len(points)))
    P = np.asarray(points)[np.asarray(cells[0].data)]
    ncell = len(P)
    vol = np.einsum("ij,ij->i", P[:, 1] - P[:, 0], np.cross(P[:, 2] - P[:, 0], P[:, 3] - P[:, 0]))
    mid = max(np.abs(P[:, 4 + k] - 0.5 * (P[:, a] + P[:, b])).max()
              for k, (a, b) in enumerate([(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]))
    print("XDMF: %d tetra10 on %d nodes, corner volumes in [%.3g, %.3g], edge nodes off the middles by %.2e"
          % (ncell, len(points), vol.min(), vol.max(), mid))
    if not (vol > 0).all() or mid > 1e-12:
        fail("tetra10 in the XDMF are not in VTK order: volume down to %.3g, edge nodes %.2e off" % (vol.min(), mid))
    if any(len(v[0]) != ncell for v in cell_data.values()) or "von_mises" not in cell_data:
        fail("XDMF cell fields %s, expected one value per element" % {k: len(v[0]) for k, v in cell_data.items()})
    tag = "p2_traction_np%d" % ARGS.ranks
    run(["-dm_plex_filename", msh, "-element", "p2", "-energy", "iarap", "-E", "1e4", "-nu", "0", "-bc_clamp",
         "bottom", "-load_traction_top", "0,0,2000", "-steps", "2", "-newton_tol", "1e-10", "-output", out_base(tag)], tag=tag)
    rest, _, x, _ = read_state(out_base(tag))
    exact = rest.copy()
    exact[:, 2] = zb + 1.2 * (rest[:, 2] - zb)
    err = np.abs(x - exact).max() / L
    print("dead traction on the top of the P2 cube: max error %.2e L (limit 1e-9)" % err)
    if not err <= 1e-9:
        fail("traction on P2: error %.2e L" % err)


CASES = {
    "hex_elements": case_hex_elements,
    "p2_elements": case_p2_elements,
}
