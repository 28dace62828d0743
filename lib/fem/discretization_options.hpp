// The options of the discretization as plain data, read once (readFemOptions) after the mesh is loaded (the element
// shape decides which apply) and before Discretization::create, which takes them. The per-cell field sources
// (cell_fields.hpp) read their own options where an energy names them (-activation, -target_file).
#pragma once

#include "energies/material.hpp"
#include "fem/boundary.hpp"
#include "mesh/mesh.hpp"
#include "fem/terms/obstacle_contact.hpp"

#include <string>
#include <vector>

namespace aries::fem {

// A material: the global one (region empty) or one -regions entry, with its uniform per-cell data.
struct MaterialOptions {
  std::string region;  // the region's gmsh physical group (id or name) as given
  energies::Material material;
  energies::UniformCellData cell;
};

struct DynamicsTerms {
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  double density = 1000.0;
};

// A load on a boundary group: a dead traction or total force (-load_traction_<set>, -load_force_<set>), a dead
// pressure (-load_pressure_<set> with -load_pressure_<set>_kind dead; all three terms/surface_loads.hpp) or a follower
// pressure (-load_pressure_<set>, terms/follower_pressure.hpp).
struct SurfaceLoad {
  enum class Kind { Traction, Force, Pressure };
  std::string set;  // the gmsh physical group, id or name, as in the option's name
  Kind kind = Kind::Traction;
  Eigen::Vector3d value = Eigen::Vector3d::Zero();  // traction (force per rest area), total force, or (p, 0, 0)
  bool dead = false;  // a pressure: dead (-load_pressure_<set>_kind dead) rather than follower
};

struct FemOptions {
  std::vector<MaterialOptions> materials;  // [0] the global material, then the -regions entries in order
  DynamicsTerms dynamics;                  // -density, -gravity
  BoundarySpec boundary;                   // -bc_clamp, -bc_box, their motions, -bc_ramp_steps
  std::string fiberFile, fiber2File;       // per-cell fibers, read where a material uses fibers ("" = none)
  bool keepOrientation = false;            // -keep_orientation (planar elements)
  double bending = 0.0;                    // -bending (cloth)
  ObstacleOptions contact;                 // 3D meshes
  std::vector<SurfaceLoad> loads;          // in the order the options were given
};

// Reads and checks every option above for the mesh's element shape (only those that apply are read, so a stray one
// stays unused). `degenerateStart`: the run starts from a scramble, invert or collapse state, static or backward Euler
// (readMaterialOptions). Errors are one line naming the option. Collective.
PetscErrorCode readFemOptions(const Mesh &mesh, bool degenerateStart, FemOptions *o);

}  // namespace aries::fem
