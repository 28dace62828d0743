// The options of mesh input (the file, its partition, where its faces are made, the element it carries), declared once
// (core/option_decl.hpp): the readers in lib/mesh, `aries -help` and docs/options.md use these.
#pragma once

#include "core/option_decl.hpp"

namespace aries::fem::opt {

using core::choiceOption;
using core::flagOption;
using core::intOption;
using core::OptionDecl;
using core::textOption;

// ---- mesh and parallel layout ----
inline constexpr OptionDecl meshFile =
    textOption("-dm_plex_filename", "FILE",
               "gmsh mesh (MSH 2.2 or 4, ASCII or binary): tetrahedra, or triangles (planar; cloth in 3D with "
               "-dm_plex_gmsh_spacedim 3); or FILE.h5, the same mesh converted by -mesh_convert, read in parallel. "
               "Scene meshes: meshes/generate.sh NAME [SIZE]")
        .otherwise("(required)");
inline constexpr OptionDecl partitioner =
    choiceOption("-partitioner", "metis|ptscotch|rcb",
                 "METIS k-way on rank 0 (through PETSc's shell partitioner; gmsh meshes only), PT-Scotch (parallel, "
                 "not deterministic from run to run) or recursive coordinate bisection of the cell centroids "
                 "(parallel, deterministic)")
        .otherwise("metis for a .msh mesh, rcb for an .h5 mesh");
inline constexpr OptionDecl meshConvert =
    textOption("-mesh_convert", "FILE.h5",
               "write the gmsh mesh -dm_plex_filename (its cells, vertices, physical groups and regions, in gmsh "
               "numbering) as an HDF5 mesh and stop; -dm_plex_filename FILE.h5 then reads it on all ranks in parallel");
inline constexpr OptionDecl gmshSpaceDim =
    intOption("-dm_plex_gmsh_spacedim", "D",
              "PETSc's: 3 keeps z for triangle meshes (cloth, -uv_map); read in 2D, a triangle surface whose z is not "
              "constant is an error unless 2 is given on purpose")
        .otherwise("2 for triangle meshes")
        .atLeast(2)
        .atMost(3);
inline constexpr OptionDecl uvMap =
    flagOption("-uv_map",
               "UV parameterization of a disk-topology triangle surface in 3D: 2D unknowns, each triangle's rest "
               "shape is its 3D triangle; output positions are the UV map with z = 0")
        .byDefault("false");

inline constexpr OptionDecl element =
    choiceOption("-element", "p1|p2",
                 "the element on a tetrahedral mesh: linear (p1, one point per cell) or quadratic (p2: 10 nodes, 4 "
                 "quadrature points; a gmsh mesh only): a node at each edge's middle, or where a second-order mesh's "
                 "10-node tetrahedra put it (curved, isoparametric). A hexahedral mesh has trilinear hexahedra")
        .byDefault("p1");

inline constexpr OptionDecl meshFaces =
    choiceOption("-mesh_faces", "distributed|serial",
                 "where a 3D mesh's faces and edges are made: by every rank for its part after the cells are "
                 "distributed (p1 or hexahedra, not -partitioner ptscotch; gmsh: ASCII, PETSc's default labels; "
                 "else as serial), or before: a gmsh mesh's on rank 0 (PETSc's reader), an HDF5 mesh's on each block")
        .byDefault("distributed");

inline constexpr const OptionDecl *kMeshOptions[] = {&meshFile, &partitioner, &meshFaces,  &meshConvert,
                                                     &gmshSpaceDim, &uvMap,    &element};

}  // namespace aries::fem::opt
