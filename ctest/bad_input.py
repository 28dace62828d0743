#!/usr/bin/env python3
"""Bad input must stop aries cleanly (registered with CTest by ctest/robustness.cmake).

usage: bad_input.py CASE --aries BIN --root REPO --work DIR [--ranks N]
       bad_input.py --list

Each case writes a malformed input (or passes a bad option) and asserts: exit code 1, exactly one line on stderr,
starting "aries: error:" and matching the case's pattern (it names the file/option and what is wrong), no traceback,
and no output file (-output, -stats) left behind. Cases run on 1 or 2 ranks (--ranks).
"""
import argparse
import os
import re
import shutil
import subprocess

import numpy as np

from harness import aries_cmd, fail, mpi_env

ARGS = None

TET_MSH = """$MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 1 "bottom"
3 1 "body"
$EndPhysicalNames
$Nodes
5
1 0 0 0
2 1 0 0
3 0 1 0
4 0 0 1
5 1 1 1
$EndNodes
$Elements
3
1 2 2 1 1 1 2 3
2 4 2 1 1 1 2 3 4
3 4 2 1 1 2 3 4 5
$EndElements
"""


# Two unit hexahedra side by side along x (gmsh node order: bottom face counterclockwise, then the top face).
HEX_MSH = """$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
12
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 0 0 1
6 1 0 1
7 2 0 0
8 2 1 0
9 1 1 1
10 0 1 1
11 2 0 1
12 2 1 1
$EndNodes
$Elements
2
1 5 2 1 1 1 2 3 4 5 6 9 10
2 5 2 1 1 2 7 8 3 6 11 12 9
$EndElements
"""


# One tetrahedron far from TET_MSH's (another body).
FAR_TET_MSH = """$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 10 0 0
2 11 0 0
3 10 1 0
4 10 0 1
$EndNodes
$Elements
1
1 4 2 1 1 1 2 3 4
$EndElements
"""


TRI_MSH = """$MeshFormat
2.2 0 8
$EndMeshFormat
$Nodes
4
1 0 0 0
2 1 0 0
3 0 1 0
4 1 1 Z
$EndNodes
$Elements
2
1 2 2 1 1 1 2 3
2 2 2 1 1 2 4 3
$EndElements
"""


def second_order_tet_msh(order):
    """One 10-node tetrahedron (corners 1-4, edge nodes 5-10 at the edges' middles), its nodes listed in `order`
    (gmsh's: corners, then the nodes on edges 01, 12, 02, 03, 23, 13)."""
    X = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    edges = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)]
    X = np.r_[X, [(X[a] + X[b]) / 2 for a, b in edges]]
    nodes = "".join("%d %g %g %g\n" % (i + 1, *x) for i, x in enumerate(X))
    return ("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10\n%s$EndNodes\n$Elements\n1\n1 11 2 1 1 %s\n"
            "$EndElements\n" % (nodes, " ".join(str(k + 1) for k in order)))


def write(name, text):
    """Writes the file atomically: cases run in parallel in one directory and share names (good.msh), so a case
    must never read another's half-written copy."""
    path = os.path.join(ARGS.work, name)
    tmp = "%s.%d.tmp" % (path, os.getpid())
    with open(tmp, "w") as fh:
        fh.write(text)
    os.replace(tmp, path)
    return path


def good_mesh():
    return write("good.msh", TET_MSH)


def plain_hdf5(name):
    """An HDF5 file that is not a converted mesh."""
    import h5py
    path = os.path.join(ARGS.work, name)
    with h5py.File(path, "w") as f:
        f["data"] = [1.0, 2.0]
    return path


def old_format_mesh(name):
    """An HDF5 file that says it is a mesh of an older aries format (PETSc's own layout, aries-mesh-1)."""
    import h5py
    path = os.path.join(ARGS.work, name)
    with h5py.File(path, "w") as f:
        f.attrs["aries_mesh_format"] = "aries-mesh-1"
        f["topology/cells"] = [0, 1, 2, 3]
    return path


def converted_mesh():
    """good.msh converted by the aries under test (-mesh_convert), on one rank."""
    out = os.path.join(ARGS.work, "good.h5")
    p = subprocess.run(aries_cmd(ARGS.aries, 1, ["-dm_plex_filename", good_mesh(), "-mesh_convert", out]),
                       capture_output=True, text=True, env=mpi_env(), cwd=ARGS.work)
    if p.returncode != 0:
        fail("converting good.msh failed: " + (p.stdout + p.stderr)[-2000:])
    return out


def fibers(n, vectors):
    return "# test fibers\n%d\n%s\n" % (n, "\n".join(vectors))


def case_defs():
    w = ARGS.work
    d = {}
    d["missing_mesh"] = (lambda: ["-dm_plex_filename", os.path.join(w, "nope.msh")],
                         r"mesh file '.*nope\.msh' \(-dm_plex_filename\) does not exist or is not readable")
    d["mesh_is_directory"] = (lambda: ["-dm_plex_filename", w], r"mesh file '.*' \(-dm_plex_filename\) is not a regular file")
    d["truncated_mesh"] = (lambda: ["-dm_plex_filename", write("trunc.msh", TET_MSH[: TET_MSH.index("$Elements") + 12])],
                           r"trunc\.msh' line \d+: file ends inside \$Elements \(truncated\?\)")
    d["wrong_node_count"] = (lambda: ["-dm_plex_filename", write("count.msh", TET_MSH.replace("$Nodes\n5\n", "$Nodes\n7\n"))],
                             r"count\.msh' line \d+: \$Nodes declares 7 entries but ends after 5 \(wrong count\?\)")
    d["unsupported_element"] = (lambda: ["-dm_plex_filename", write("prism.msh", TET_MSH.replace(
        "3 4 2 1 1 2 3 4 5", "3 6 2 1 1 1 2 3 4 5 1"))],
                                r"prism\.msh' line \d+: unsupported element type 6 \(6-node prism\)")
    # Tags, counts and types are integers of at most 2^31 - 1: a larger one is refused before it is converted to an int
    # (the conversion is undefined behaviour; clang's UBSan found it in the fuzz test).
    d["huge_element_type"] = (lambda: ["-dm_plex_filename", write("hugetype.msh", TET_MSH.replace(
        "3 4 2 1 1 2 3 4 5", "3 -4.97909e+12 2 1 1 2 3 4 5"))],
                              r"hugetype\.msh' line \d+: number 2 of a \$Elements line, -4979090000000, is not an integer "
                              r"between -2147483647 and 2147483647")
    # MSH 4.0 lays out $Entities and $Nodes differently from 4.1 (which gmsh has written since 2018).
    d["gmsh_format_40"] = (lambda: ["-dm_plex_filename", write("v40.msh", TET_MSH.replace("2.2 0 8", "4 0 8"))],
                           r"v40\.msh' line 2: unsupported gmsh format version 4 \(2\.x and 4\.1 are supported: save the "
                           r"mesh as MSH 4\.1 or 2\.2\)")
    d["fractional_node_tag"] = (lambda: ["-dm_plex_filename", write("fractag.msh", TET_MSH.replace("\n5 1 1 1\n",
                                                                                                  "\n5.5 1 1 1\n"))],
                                r"fractag\.msh' line \d+: number 1 of a \$Nodes line, 5\.5, is not an integer")
    # A 10-node tetrahedron whose edge nodes are not in gmsh's order (nodes 8 and 9 swapped) is refused by -element
    # p2, which places them; the same file in order is read (the e2e tests run second-order meshes).
    d["second_order_node_order"] = (lambda: ["-dm_plex_filename", write("tet10_order.msh", second_order_tet_msh(
        [0, 1, 2, 3, 4, 5, 6, 7, 9, 8])), "-element", "p2"],
                                    r"tet10_order\.msh': the edge node at \(0, 0\.5, 0\.5\) lies 0\.5 edge lengths from "
                                    r"the middle of its edge \(.*\) \(more than 0\.25\); the 10-node tetrahedra must "
                                    r"list their nodes in gmsh's order")
    d["gmsh_highorder_field"] = (lambda: ["-dm_plex_filename", write("tet10.msh", second_order_tet_msh(range(10))),
                                          "-dm_plex_gmsh_highorder", "true"],
                                 r"option -dm_plex_gmsh_highorder: aries reads a second-order gmsh mesh as its "
                                 r"corners, and -element p2 takes the edge nodes from the file itself; remove the option")
    d["mixed_cells"] = (lambda: ["-dm_plex_filename", write("mixed.msh", HEX_MSH.replace(
        "$EndNodes", "13 0.5 0.5 -1\n$EndNodes").replace("$Elements\n2\n", "$Elements\n3\n").replace(
        "$EndElements", "3 4 2 1 1 1 2 4 13\n$EndElements").replace("$Nodes\n12\n", "$Nodes\n13\n"))],
                        r"mixed\.msh' \(-dm_plex_filename\) has cells of type tetrahedron, hexahedron; aries needs one "
                        r"cell type")
    d["quadrangles_in_tet_mesh"] = (lambda: ["-dm_plex_filename", write("quads.msh", TET_MSH.replace(
        "$Elements\n3\n", "$Elements\n4\n").replace("$EndElements", "4 3 2 1 1 1 2 5 3\n$EndElements"))],
                                    r"quads\.msh' line \d+: quadrangles \(element type 3\) are read as faces of "
                                    r"hexahedra, and the file has no hexahedra")
    d["face_not_of_a_cell"] = (lambda: ["-dm_plex_filename", write("strayface.msh", TET_MSH.replace(
        "1 2 2 1 1 1 2 3\n", "1 2 2 1 1 1 2 5\n"))],
                               r"strayface\.msh' \(-dm_plex_filename\): a face of physical group 1 \(corner at "
                               r"\(0, 0, 0\)\) is not a face of any cell")
    d["folded_hexahedron"] = (lambda: ["-dm_plex_filename", write("folded.msh", HEX_MSH.replace(
        "2 5 2 1 1 2 7 8 3 6 11 12 9", "2 5 2 1 1 2 7 3 8 6 11 12 9"))],
                              r"cell 1 .*degenerate: rest volume 0 \(det J <= 0 at some Gauss point: a folded hexahedron")
    d["gamg_on_baij"] = (lambda: ["-dm_plex_filename", good_mesh(), "-pc_type", "gamg", "-dm_mat_type", "baij"],
                         r"option -pc_type gamg: PETSc 3.18's GAMG cannot coarsen -dm_mat_type baij matrices; give "
                         r"-dm_mat_type aij")
    d["p2_on_hexahedra"] = (lambda: ["-dm_plex_filename", write("hexes.msh", HEX_MSH), "-element", "p2"],
                            r"option -element p2: mesh '.*hexes\.msh' has hexahedra, which are trilinear by the mesh")
    d["p2_on_hdf5"] = (lambda: ["-dm_plex_filename", converted_mesh(), "-element", "p2"],
                       r"option -element p2: the edge nodes are numbered on the serial gmsh mesh; '.*good\.h5' is an "
                       r"HDF5 mesh")
    d["not_gmsh"] = (lambda: ["-dm_plex_filename", write("junk.msh", "hello world\n")],
                     r"junk\.msh' line 1: not a gmsh file: it does not start with \$MeshFormat")
    d["degenerate_cell"] = (lambda: ["-dm_plex_filename", write("flat.msh", TET_MSH.replace("5 1 1 1", "5 1 1 0").replace(
        "3 4 2 1 1 2 3 4 5", "3 4 2 1 1 2 3 5 1"))],
                            r"cell 1 .*degenerate: rest volume")
    d["inverted_cell"] = (lambda: ["-dm_plex_filename", write("inv.msh", TET_MSH.replace("3 4 2 1 1 2 3 4 5",
                                                                                          "3 4 2 1 1 3 2 4 5"))],
                          r"cell \d .*inverted: signed rest volume")
    d["fiber_count"] = (lambda: ["-dm_plex_filename", good_mesh(), "-energy", "fiber", "-gamma", "1", "-fiber_file",
                                 write("f3.txt", fibers(3, ["1 0 0"] * 3))],
                        r"-fiber_file file '.*f3\.txt' declares 3 cells but the mesh has 2")
    d["fiber_count_huge"] = (lambda: ["-dm_plex_filename", good_mesh(), "-energy", "fiber", "-gamma", "1", "-fiber_file",
                                      write("fhuge.txt", fibers(2, ["1 0 0"] * 2).replace("\n2\n", "\n1e300\n"))],
                             r"-fiber_file file '.*fhuge\.txt' declares 1e300 cells but the mesh has 2")
    d["fiber_zero"] = (lambda: ["-dm_plex_filename", good_mesh(), "-energy", "fiber", "-gamma", "1", "-fiber_file",
                                write("f0.txt", fibers(2, ["1 0 0", "0 0 0"]))],
                       r"-fiber_file file '.*f0\.txt' line 4: zero-length vector for cell 1")
    d["target_keyframe_order"] = (lambda: ["-dm_plex_filename", good_mesh(), "-energy", "shape_target", "-target_file",
                                           write("kf.txt", "cells 2 keyframes 2\ntime 1\n1 1 1 0 0 0\n1 1 1 0 0 0\n"
                                                 "time 0.5\n1 1 1 0 0 0\n1 1 1 0 0 0\n")],
                                  r"-target_file '.*kf\.txt' line 5: keyframe times must increase \(0\.5 after 1\)")
    d["target_keyframe_count_huge"] = (lambda: ["-dm_plex_filename", good_mesh(), "-energy", "shape_target",
                                                 "-target_file", write("kh.txt", "cells 2 keyframes 2000000000\ntime 0\n"
                                                                       "1 1 1 0 0 0\n1 1 1 0 0 0\n")],
                                      r"-target_file '.*kh\.txt' declares 2000000000 keyframes of 2 cells, more than its "
                                      r"\d+ bytes can hold")
    d["target_keyframe_short"] = (lambda: ["-dm_plex_filename", good_mesh(), "-energy", "shape_target", "-target_file",
                                           write("ks.txt", "cells 2 keyframes 1\ntime 0\n1 1 1 0 0\n")],
                                  r"-target_file '.*ks\.txt' line 3: expected 6 numbers \(s11 s22 s33 s12 s23 s13\), got 5")
    d["fiber_short"] = (lambda: ["-dm_plex_filename", good_mesh(), "-energy", "fiber", "-gamma", "1", "-fiber_file",
                                 write("fs.txt", fibers(2, ["1 0 0"]))],
                        r"-fiber_file file '.*fs\.txt' has 1 vectors for 2 cells")
    d["unknown_energy"] = (lambda: ["-dm_plex_filename", good_mesh(), "-energy", "neohookean"],
                           r"option -energy: unknown energy 'neohookean'")
    d["unknown_singularity"] = (lambda: ["-dm_plex_filename", good_mesh(), "-singularity", "magic"],
                                r"option -singularity: 'magic' is not none\|mollifier\|barrier")
    d["E_not_a_number"] = (lambda: ["-dm_plex_filename", good_mesh(), "-E", "1e4x"],
                           r"option -E: '1e4x' is not a finite number")
    d["E_nan"] = (lambda: ["-dm_plex_filename", good_mesh(), "-E", "nan"], r"option -E: 'nan' is not a finite number")
    d["E_negative"] = (lambda: ["-dm_plex_filename", good_mesh(), "-E", "-5"], r"option -E must be > 0 \(got -5\)")
    d["nu_half"] = (lambda: ["-dm_plex_filename", good_mesh(), "-nu", "0.5"],
                    r"option -nu must be in \[0, 0\.5\) \(got 0\.5\)")
    d["dt_negative"] = (lambda: ["-dm_plex_filename", good_mesh(), "-dt", "-1e-2"], r"option -dt must be > 0")
    d["density_zero"] = (lambda: ["-dm_plex_filename", good_mesh(), "-density", "0"], r"option -density must be > 0")
    d["unknown_bc_set"] = (lambda: ["-dm_plex_filename", good_mesh(), "-bc_clamp", "top"],
                           r"option -bc_clamp: boundary set 'top' does not exist in mesh .*physical groups present")
    d["clamp_components_unknown"] = (lambda: ["-dm_plex_filename", good_mesh(), "-bc_clamp", "1",
                                              "-bc_clamp_1_components", "x,w"],
                                     r"option -bc_clamp_1_components: 'w' is not a component \(components are x, y, z")
    d["clamp_components_twice"] = (lambda: ["-dm_plex_filename", good_mesh(), "-bc_box", "0,1,0,1,0,1",
                                            "-bc_box_1_components", "z,z"],
                                   r"option -bc_box_1_components: 'z' is listed twice")
    d["clamp_components_z_2d"] = (lambda: ["-dm_plex_filename", write("flat_tri.msh", TRI_MSH.replace("Z", "0")),
                                           "-bc_box", "0,0.1,0,0.1,-1,1", "-bc_box_1_components", "x,z"],
                                  r"option -bc_box_1_components: z on a 2D mesh \(use x, y\)")
    d["load_unknown_set"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_traction_top", "0,0,1"],
                             r"option -load_traction_top: no such physical group in mesh .*physical groups present")
    d["load_volume_group"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_force_body", "0,0,1"],
                              r"option -load_force_body: the group has no boundary facets")
    d["load_components"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_force_bottom", "1,2"],
                            r"option -load_force_bottom takes 3 comma-separated numbers on a 3D mesh, got 2")
    d["load_pressure_open"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_pressure_bottom", "1"],
                               r"option -load_pressure_bottom: the group is not a closed surface \(3 edges.*"
                               r"-load_pressure_bottom_kind dead gives the dead pressure")
    d["load_pressure_kind_unknown"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_pressure_bottom", "1",
                                                "-load_pressure_bottom_kind", "normal"],
                                       r"option -load_pressure_bottom_kind: 'normal' is not follower\|dead")
    # The kind is not read as a set named "bottom_kind": without its pressure it is an error naming both options.
    d["load_pressure_kind_alone"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_pressure_bottom_kind", "dead"],
                                     r"option -load_pressure_bottom_kind: no pressure -load_pressure_bottom is given")
    d["load_pressure_no_faces"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_pressure_body", "1",
                                            "-load_pressure_body_kind", "dead"],
                                   r"option -load_pressure_body: the group has no boundary facets .*a dead pressure "
                                   r"acts on a boundary group")
    d["load_pressure_unknown_set"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_pressure_inner", "1"],
                                      r"option -load_pressure_inner: no such physical group .*"
                                      r"-load_pressure_inner_kind dead loads an open one")
    d["load_pressure_follower_planar"] = (lambda: ["-dm_plex_filename", write("flat_tri.msh", TRI_MSH.replace("Z", "0")),
                                                   "-load_pressure_1", "1"],
                                          r"option -load_pressure_1: a follower pressure acts on the closed surfaces "
                                          r"of a volume mesh; on a planar mesh -load_pressure_1_kind dead")
    d["load_not_a_number"] = (lambda: ["-dm_plex_filename", good_mesh(), "-load_traction_bottom", "0,x,1"],
                              r"option -load_traction_bottom: ")
    d["strict_unknown_option"] = (lambda: ["-dm_plex_filename", good_mesh(), "-strict", "-gama", "3"],
                                  r"-strict: unknown or unused option\(s\) -gama")
    d["restart_garbage"] = (lambda: ["-dm_plex_filename", good_mesh(), "-restart", write("ck.h5", "not hdf5")],
                            r"cannot open checkpoint '.*ck\.h5' \(-restart\)")
    d["psd_projection_unknown"] = (lambda: ["-dm_plex_filename", good_mesh(), "-psd_projection", "flip"],
                                   r"option -psd_projection: 'flip' is not clamp\|abs\|adaptive\|none")
    d["psd_eigensystem_unknown"] = (lambda: ["-dm_plex_filename", good_mesh(), "-psd_eigensystem", "svd"],
                                    r"option -psd_eigensystem: 'svd' is not analytic\|numeric")
    d["newton_subspace_range"] = (lambda: ["-dm_plex_filename", good_mesh(), "-newton_subspace", "9"],
                                  r"option -newton_subspace must be in 0\.\.7 \(got 9\)")
    d["newton_rotation_range"] = (lambda: ["-dm_plex_filename", good_mesh(), "-newton_rotation", "7"],
                                  r"option -newton_rotation must be in -1\.\.6 \(got 7\)")
    d["static_detached_start_value"] = (lambda: ["-dm_plex_filename", good_mesh(), "-static_detached_start", "maybe"],
                                        r"-static_detached_start")
    d["static_detached_shape_first_value"] = (lambda: ["-dm_plex_filename", good_mesh(), "-initial", "scramble",
                                                       "-static_detached_shape_first", "maybe"],
                                              r"-static_detached_shape_first")
    d["newton_forcing_range"] = (lambda: ["-dm_plex_filename", good_mesh(), "-newton_forcing", "1.5"],
                                 r"option -newton_forcing must be in \[0, 1\) \(got 1\.5\)")
    d["missing_options_file"] = (lambda: ["-options_file", os.path.join(w, "nope.yml")],
                                 r"options file '.*nope\.yml' \(-options_file\) does not exist or is not readable")
    d["curved_surface_read_flat"] = (lambda: ["-dm_plex_filename", write("curved.msh", TRI_MSH.replace("Z", "0.5"))],
                                     r"curved\.msh' is a triangle surface that is not flat \(z varies by 0\.5\) but "
                                     r"would be read in 2D with z dropped: pass -dm_plex_gmsh_spacedim 3")
    d["cloth_energy_planar_mesh"] = (lambda: ["-dm_plex_filename", write("flat_tri.msh", TRI_MSH.replace("Z", "0")),
                                              "-energy", "bw46s"],
                                     r"option -energy: energy 'bw46s' is not defined for planar triangle .*"
                                     r"-dm_plex_gmsh_spacedim 3")
    d["output_field_unknown"] = (lambda: ["-dm_plex_filename", good_mesh(), "-output_fields", "alpha,stress"],
                                 r"option -output_fields: 'stress' is not a field \(alpha\|.*\|marker, or all\)")
    d["output_velocity_static"] = (lambda: ["-dm_plex_filename", good_mesh(), "-output_fields", "velocity"],
                                   r"option -output_fields: 'velocity' needs -integrator beuler")
    d["h5_mesh_missing"] = (lambda: ["-dm_plex_filename", os.path.join(w, "nope.h5")],
                            r"cannot open mesh '.*nope\.h5' \(-dm_plex_filename\)")
    d["h5_mesh_not_hdf5"] = (lambda: ["-dm_plex_filename", write("junk.h5", "hello world\n")],
                             r"mesh '.*junk\.h5' \(-dm_plex_filename\) is not an HDF5 file")
    d["h5_mesh_not_converted"] = (lambda: ["-dm_plex_filename", plain_hdf5("plain.h5")],
                                  r"plain\.h5' \(-dm_plex_filename\) is an HDF5 file but not a mesh converted by aries "
                                  r"\(make one with aries -dm_plex_filename MESH\.msh -mesh_convert")
    d["h5_mesh_old_format"] = (lambda: ["-dm_plex_filename", old_format_mesh("old.h5")],
                               r"mesh '.*old\.h5' \(-dm_plex_filename\) was converted by an older aries \(format "
                               r"aries-mesh-1, this one reads aries-mesh-2\); convert it again with -mesh_convert")
    d["h5_mesh_metis"] = (lambda: ["-dm_plex_filename", converted_mesh(), "-partitioner", "metis"],
                          r"option -partitioner metis: METIS partitions the whole mesh on rank 0, but '.*good\.h5' is "
                          r"read in parallel")
    d["mesh_convert_suffix"] = (lambda: ["-dm_plex_filename", good_mesh(), "-mesh_convert", os.path.join(w, "out.msh")],
                                r"option -mesh_convert '.*out\.msh': the converted mesh's name must end in \.h5")
    # -coarse_mesh (nested iteration): a coarse mesh that is not coarser, of another body, missing; a surface mesh.
    d["coarse_mesh_not_coarser"] = (lambda: ["-dm_plex_filename", good_mesh(), "-coarse_mesh", good_mesh()],
                                    r"option -coarse_mesh: '.*good\.msh' has 2 cells, not fewer than the 2 of '.*good"
                                    r"\.msh' \(coarse meshes come coarsest last\)")
    d["coarse_mesh_other_body"] = (lambda: ["-dm_plex_filename", good_mesh(), "-coarse_mesh",
                                            write("far.msh", FAR_TET_MSH)],
                                   r"option -coarse_mesh \('.*far\.msh' for '.*good\.msh'\), its cell centroids: a "
                                   r"point of '.*far\.msh' is farther than the largest cell .* from every cell of "
                                   r"'.*good\.msh': the two meshes are not of the same body")
    d["coarse_mesh_missing"] = (lambda: ["-dm_plex_filename", good_mesh(), "-coarse_mesh",
                                         os.path.join(ARGS.work, "missing.msh")],
                                r"mesh file '.*missing\.msh' \(-coarse_mesh\) does not exist or is not readable")
    d["coarse_mesh_truncated"] = (lambda: ["-dm_plex_filename", good_mesh(), "-coarse_mesh",
                                           write("trunc_coarse.msh", TET_MSH[: TET_MSH.index("$Elements") + 12])],
                                  r"trunc_coarse\.msh' line \d+: file ends inside \$Elements \(truncated\?\)")
    d["coarse_mesh_surface"] = (lambda: ["-dm_plex_filename", write("flat_tri.msh", TRI_MSH.replace("Z", "0")),
                                         "-coarse_mesh", good_mesh()],
                                r"option -coarse_mesh: nested iteration needs linear tetrahedra, and '.*flat_tri\.msh' "
                                r"is a surface mesh")
    return d


def run_case(name):
    args, pattern = case_defs()[name]
    outdir = os.path.join(ARGS.work, "out_" + name)
    shutil.rmtree(outdir, ignore_errors=True)
    full = args() + ["-output", os.path.join(outdir, "o"), "-stats", os.path.join(outdir, "stats.csv")]
    cmd = aries_cmd(ARGS.aries, ARGS.ranks, full)
    print("$ " + " ".join(cmd))
    p = subprocess.run(cmd, capture_output=True, text=True, env=mpi_env(), cwd=ARGS.work, timeout=120)
    err = [l for l in p.stderr.splitlines() if l.strip()]
    print("exit %d; stderr:\n%s" % (p.returncode, "\n".join(err)))
    if p.returncode != 1:
        fail("exit code %d, expected 1" % p.returncode)
    if len(err) != 1:
        fail("expected exactly one line on stderr, got %d" % len(err))
    if not err[0].startswith("aries: error: "):
        fail("the line does not start with 'aries: error: '")
    if not re.search(pattern, err[0]):
        fail("the message does not match /%s/" % pattern)
    if "PETSC ERROR" in p.stdout + p.stderr:
        fail("a PETSc traceback was printed")
    if os.path.exists(outdir) and any(files for _, _, files in os.walk(outdir)):
        fail("output files were left behind: %s" % [f for _, _, fs in os.walk(outdir) for f in fs])


def main():
    global ARGS
    ap = argparse.ArgumentParser()
    ap.add_argument("case", nargs="?")
    ap.add_argument("--aries")
    ap.add_argument("--root")
    ap.add_argument("--work", default="/tmp/aries-bad-input")
    ap.add_argument("--ranks", type=int, default=1)
    ap.add_argument("--list", action="store_true")
    ARGS = ap.parse_args()
    if ARGS.list:
        print(";".join(case_defs()))
        return
    os.makedirs(ARGS.work, exist_ok=True)
    if ARGS.case not in case_defs():
        fail("unknown case %s" % ARGS.case)
    run_case(ARGS.case)
    print("PASS")


if __name__ == "__main__":
    main()
