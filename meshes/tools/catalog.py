#!/usr/bin/python3
"""The mesh catalog: every mesh's fixed size presets (meshes/generate.sh asks it on every call, so it imports nothing
beyond the standard library: a cached mesh's lookup must not pay numpy's import). Usable directly:

    catalog.py list                    names, sizes, kinds, parameters, expected cell counts
    catalog.py names                   the mesh names, one per line
    catalog.py resolve NAME SIZE       canonical size name (aliases such as cube/paper -> default)

tools/build.py builds the meshes from these entries.
"""

import math
import sys

# --------------------------------------------------------------------------------------------------
# Catalog. 'tets' (volume meshes) / 'triangles' (surface meshes) is the count this generator
# produces with Debian 12's gmsh 4.8.4 (it is deterministic); a different count only warns (another
# gmsh version meshes differently). 'alias' maps a size name to another entry of the same mesh.

def cook_sizes(cells, per_square):
    """The Cook panel's sizes: n x n grid squares (test 8, s16, default 32, s64, s128), `per_square` cells each."""
    sizes = {}
    for name, n in (("test", 8), ("s16", 16), ("default", 32), ("paper", None), ("s64", 64), ("s128", 128)):
        sizes[name] = {"alias": "default"} if n is None else {"n": n, cells: per_square * n * n}
    return sizes


def tube_sizes(cells, per_cell):
    """The quarter tube's sizes: n cells across the wall (test 2, default 4, s8, s16, s32), tube_cells(n) around it."""
    sizes = {}
    for name, n in (("test", 2), ("default", 4), ("paper", None), ("s8", 8), ("s16", 16), ("s32", 32)):
        sizes[name] = {"alias": "default"} if n is None else {"n": n, cells: per_cell * n * tube_cells(n)}
    return sizes


def tube_cells(n):
    """Cells around the quarter tube for n across its wall: about square at the mean radius 1.5 (arc pi/2 1.5)."""
    return int(round(n * math.pi / 2 * 1.5))


CATALOG = {
    "cylinder": {
        "test": {"h": 0.17, "tets": 1770},
        # verification (bench/verification.py: P1 against P2 on the compressed cylinder)
        "s12": {"h": 0.12, "tets": 4708},
        "s05": {"h": 0.05, "tets": 59184},
        "s300k": {"h": 0.029, "tets": 292782},  # the peer issue's large static compression (bench/peer.py cylinder)
        "default": {"h": 0.076, "tets": 17782},
        "paper": {"alias": "default"},
    },
    "cube": {
        "test": {"n": 6, "tets": 6 * 6 ** 3},
        "mid": {"n": 12, "tets": 6 * 12 ** 3},  # verification: the convergence study's middle size
        "default": {"n": 18, "tets": 6 * 18 ** 3},
        "paper": {"alias": "default"},
        "fine": {"n": 24, "tets": 6 * 24 ** 3},
        "s384k": {"n": 40, "tets": 6 * 40 ** 3},  # scale-out: 384,000 tets (solver crossover, bench/scale_out.py)
        "s1m": {"n": 56, "tets": 6 * 56 ** 3},  # scale-out: 1,053,696 tets (solver crossover, bench/scale_out.py)
        "s2m": {"n": 70, "tets": 6 * 70 ** 3},  # scale-out: 2,058,000 tets (parallel input and output)
    },
    # the peer benchmark (bench/peer.py): a box 1 x 1 x 2 compressed along z by its supports, 10k to 1M tets
    "box": {
        "test": {"h": 0.2, "tets": 1292},
        "s10k": {"h": 0.096, "tets": 10029},
        "s40k": {"h": 0.06, "tets": 38633},
        "default": {"h": 0.04, "tets": 125877},
        "paper": {"alias": "default"},
        "s400k": {"h": 0.0273, "tets": 388582},
        "s1m": {"h": 0.0198, "tets": 1004954},
    },
    "hexcube": {  # trilinear hexahedra (Q1): the unit cube as an n^3 grid; "warped" moves its interior nodes
        "test": {"n": 6, "hexes": 6 ** 3},
        "warped": {"n": 4, "jitter": 0.2, "hexes": 4 ** 3},
        "mid": {"n": 12, "hexes": 12 ** 3},
        "default": {"n": 18, "hexes": 18 ** 3},
        "paper": {"alias": "default"},
        "fine": {"n": 24, "hexes": 24 ** 3},
        # verification: the same grids with their interior nodes moved by up to 0.2 of a cell (general hexahedra)
        "wtest": {"n": 6, "jitter": 0.2, "hexes": 6 ** 3},
        "wmid": {"n": 12, "jitter": 0.2, "hexes": 12 ** 3},
        "wdefault": {"n": 18, "jitter": 0.2, "hexes": 18 ** 3},
        "wfine": {"n": 24, "jitter": 0.2, "hexes": 24 ** 3},
    },
    "armadillo": {
        "coarse": {"h": 0.14, "tets": 746},  # nested iteration: a coarse level of the test mesh
        "test": {"h": 0.07, "tets": 3816},
        "default": {"h": 0.0315, "tets": 34320},
        "paper": {"alias": "default"},
        "fig15": {"h": 0.0155, "tets": 262925},  # caricature (Fig. 15, Table 1: 292,476 tets)
    },
    "bunny": {
        "coarse": {"h": 0.13, "tets": 607},  # nested iteration: a coarse level of the test mesh
        "test": {"h": 0.066, "tets": 3513},
        "default": {"h": 0.0289, "tets": 35010},
        "paper": {"h": 0.0107, "tets": 639254},
        "fig15": {"h": 0.0143, "tets": 271096},  # caricature (Fig. 15, Table 1: 292,476 tets)
        "hextest": {"voxel": 0.03, "hexes": 7401},  # voxel hexahedra, a test size (at 0.04 the ears are 1 voxel thick)
        "hexmid": {"voxel": 0.02, "hexes": 24850},  # voxel hexahedra between the two (the interaction's tail, issue 45)
        "hex": {"voxel": 0.01, "hexes": 199368},  # voxel hexahedra: the paper's Fig. 13 mesh size (200,739 hexahedra)
    },
    "octopus": {
        "test": {"hmax": 0.4, "ncurv": 5, "tets": 4030},
        "default": {"hmax": 0.106, "ncurv": 27, "tets": 314819},
        "paper": {"alias": "default"},
    },
    # closed CGAL surfaces beyond the paper's scenes: shapes the solver was not developed on
    "triceratops": {
        "coarse": {"h": 0.076, "tets": 848},  # nested iteration: a coarse level of the test mesh
        "test": {"h": 0.038, "tets": 4620},
        "default": {"h": 0.019, "tets": 30238},
        "paper": {"alias": "default"},
    },
    "hand": {
        "coarse": {"h": 0.124, "tets": 723},  # nested iteration: a coarse level of the test mesh
        "test": {"h": 0.062, "tets": 4622},
        "default": {"h": 0.031, "tets": 34096},
        "paper": {"alias": "default"},
    },
    "camel": {
        "coarse": {"h": 0.08, "tets": 941},  # nested iteration (HXT fails on the legs from h = 0.085)
        "test": {"h": 0.06, "tets": 1832},
        "default": {"h": 0.025, "tets": 16638},
        "paper": {"alias": "default"},
    },
    # a fourth such surface, for checks of a default on a shape none of its measurements used (bench/
    # degenerate_starts.py --meshes bear)
    "bear": {
        "test": {"h": 0.08, "tets": 4454},
        "default": {"h": 0.04, "tets": 31998},
        "paper": {"alias": "default"},
        # voxel hexahedra: a second body for the local solve's check on rigid handles (-newton_local_solve)
        "hexmid": {"voxel": 0.03, "hexes": 17783},
    },
    # two more, added when the bear's result was to be checked on shapes no default was measured on
    # (bench/degenerate_starts.py --meshes bull,homer)
    "bull": {
        "test": {"h": 0.07, "tets": 3833},
        "default": {"h": 0.033, "tets": 28648},
        "paper": {"alias": "default"},
    },
    "homer": {
        "test": {"h": 0.065, "tets": 2853},
        "default": {"h": 0.03, "tets": 24277},
        "paper": {"alias": "default"},
    },
    # verification: Lame's thick sphere under internal pressure (inner radius 0.5, outer 1), h = 0.2 ... 0.05
    "shell": {
        "coarse": {"h": 0.3, "tets": 960},  # P2's coarsest in the inflation (bench/verification.py)
        "test": {"h": 0.2, "tets": 2338},
        "default": {"h": 0.1, "tets": 18040},
        "paper": {"alias": "default"},
        "fine3": {"h": 0.07, "tets": 50330},
        "fine4": {"h": 0.05, "tets": 138260},
        "fine5": {"h": 0.035, "tets": 393067},
    },
    # verification: Lame's thick sphere (inner radius 0.5, outer 1) in trilinear hexahedra: a cubed sphere, n x n cells
    # per cube face and n / 2 radial layers (6 n^2 n/2 hexes)
    "shell_hex": {
        "test": {"n": 4, "hexes": 3 * 4 ** 3},
        "default": {"n": 8, "hexes": 3 * 8 ** 3},
        "paper": {"alias": "default"},
        "s12": {"n": 12, "hexes": 3 * 12 ** 3},
        "s16": {"n": 16, "hexes": 3 * 16 ** 3},
        "s20": {"n": 20, "hexes": 3 * 20 ** 3},  # about the nodes of P2 on the h = 0.1 shell (24.3k vs 27.8k)
        "s24": {"n": 24, "hexes": 3 * 24 ** 3},
    },
    # verification: Lame's thick cylinder in plane strain, a quarter (inner radius 1, outer 2, one cell layer in z),
    # n cells across the wall (bench/verification.py); P1 / P2 on "tube", trilinear hexahedra on "tube_hex"
    "tube": tube_sizes("tets", 6),
    "tube_curved": tube_sizes("tets", 6),  # "tube" with curved edge nodes (10-node tets)
    "tube_hex": tube_sizes("hexes", 1),
    # triangle surface meshes
    "cloth": {
        "test": {"n": 16, "triangles": 2 * 16 ** 2},
        "default": {"n": 128, "triangles": 2 * 128 ** 2},
        "paper": {"alias": "default"},
    },
    # verification: a cantilever 10 long, 1 deep (nx x nx/10 cells)
    "beam": {
        "test": {"nx": 40, "triangles": 2 * 40 * 4},
        "default": {"nx": 80, "triangles": 2 * 80 * 8},
        "paper": {"alias": "default"},
        "s160": {"nx": 160, "triangles": 2 * 160 * 16},
        "s320": {"nx": 320, "triangles": 2 * 320 * 32},
    },
    # verification: Cook's membrane (a tapered panel, 48 wide, left edge 44 high, right edge 16 high), n x n panels
    "cook": cook_sizes("triangles", 2),
    # verification: Cook's membrane as a thin 3D slab, its half z in [0, 1/2] (n x n x 1 cells, 6 tets each)
    "cook_slab": cook_sizes("tets", 6),
    "cook_slab_full": cook_sizes("tets", 12),  # the whole slab, z in [-1/2, 1/2]: cook_slab and its mirror image
    "cook_hex": cook_sizes("hexes", 1),  # the same slab in trilinear hexahedra (n x n x 1)
    "disk": {
        "test": {"rings": 10, "triangles": 6 * 10 ** 2},
        "default": {"rings": 15, "triangles": 6 * 15 ** 2},
        "paper": {"alias": "default"},
    },
    "lionhead": {
        "test": {"h": 0.05, "triangles": 1962},
        "default": {"triangles": 16674},  # the source mesh as is
        "paper": {"alias": "default"},
    },
    "nefertiti": {
        "test": {"alias": "default"},  # the source mesh is already small
        "default": {"triangles": 562},
        "paper": {"alias": "default"},
    },
}
# "shell" (the same corners, all its sizes but fine5) as gmsh's second-order mesh: 10-node tets, edge nodes on the spheres
CATALOG["shell_curved"] = {size: dict(p) for size, p in CATALOG["shell"].items() if size != "fine5"}

PAPER = {  # the paper's meshes (Table 1: tets, Table 2: cloth triangles), for the listing
    "cylinder": "17,840",
    "cube": "34,992 (pull) / 54,985 (compress)",
    "armadillo": "34,992",
    "bunny": "637,584",
    "octopus": "308,200",
    "triceratops": "(not in the paper)",
    "hand": "(not in the paper)",
    "camel": "(not in the paper)",
    "bear": "(not in the paper)",
    "bull": "(not in the paper)",
    "homer": "(not in the paper)",
    "cloth": "32,768",
    "disk": "(not in the paper)",
    "shell": "(verification: Lame's sphere)",
    "box": "(peer benchmark: DOLFINx, bench/peer.py)",
    "cook": "(verification: Cook's membrane)",
    "cook_slab": "(verification: Cook's membrane, 3D slab)",
    "cook_slab_full": "(verification: Cook's membrane, the whole 3D slab)",
    "cook_hex": "(verification: Cook's membrane, 3D slab, hexahedra)",
    "beam": "(verification: cantilever)",
    "tube": "(verification: Lame's thick cylinder, plane strain)",
    "shell_hex": "(verification: Lame's sphere, hexahedra)",
    "tube_hex": "(verification: Lame's thick cylinder, plane strain, hexahedra)",
    "shell_curved": "(verification: Lame's sphere, second-order tets)",
    "tube_curved": "(verification: Lame's thick cylinder, second-order tets)",
    "lionhead": "Fig. 14 (count not given)",
    "nefertiti": "Fig. 14 (count not given)",
}


def kind(name, size=None):
    """'tet', 'tri' or 'hex' (the catalog entry's count key; the bunny has tet and hex sizes)."""
    entries = [CATALOG[name][resolve(name, size)]] if size else CATALOG[name].values()
    if any("hexes" in p for p in entries) and (size or all("hexes" in p for p in entries if "alias" not in p)):
        return "hex"
    return "tri" if any("triangles" in p for p in entries) else "tet"


CELL_KEY = {"tet": "tets", "tri": "triangles", "hex": "hexes"}


def resolve(name, size):
    if name not in CATALOG:
        raise SystemExit("unknown mesh '%s' (known: %s)" % (name, ", ".join(CATALOG)))
    sizes = CATALOG[name]
    if size not in sizes:
        raise SystemExit("mesh '%s' has no size '%s' (sizes: %s); sizes are fixed presets so that "
                         "generation stays bounded in time and memory" % (name, size, ", ".join(sizes)))
    return sizes[size].get("alias", size)


def listing():
    print("%-11s %-8s %-5s %-8s %-22s %s" % ("name", "size", "kind", "cells", "parameters",
                                                  "paper (Table 1 tets, Table 2 triangles)"))
    for name, sizes in CATALOG.items():
        paper_size = resolve(name, "paper")
        for size, p in sizes.items():
            if "alias" in p:
                print("%-11s %-8s %-5s %-8s %-22s" % (name, size, kind(name, size), "", "= " + p["alias"]))
                continue
            cells = CELL_KEY[kind(name, size)]
            par = " ".join("%s=%g" % (k, v) for k, v in p.items() if k != cells) or "source mesh"
            paper = PAPER.get(name, "(not in the paper)") if size == paper_size else ("292,476 (Fig. 15)" if size == "fig15" else "")
            print("%-11s %-8s %-5s %-8s %-22s %s" % (name, size, kind(name, size), p.get(cells, "?"), par, paper))


def main(argv):
    if len(argv) >= 1 and argv[0] == "list":
        listing()
    elif len(argv) == 1 and argv[0] == "names":
        print("\n".join(CATALOG))
    elif len(argv) == 3 and argv[0] == "resolve":
        print(resolve(argv[1], argv[2]))
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    main(sys.argv[1:])
