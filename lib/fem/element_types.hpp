// The element types the discretization runs, one registration line each (the types themselves: kernels/elements/).
// ARIES_ELEMENT_TYPES(X, ARG) calls X(E, ARG) for each: the explicit instantiations of the discretization's parts
// (ARIES_INSTANTIATE_FOR_ELEMENT_TYPES) and the choice of element for a mesh (Discretization::create) both expand it,
// so adding an element type is its file plus one line here (docs/elements.md, "Adding an element type").
#pragma once

#include "kernels/elements/hex8.hpp"
#include "kernels/elements/simplex.hpp"
#include "kernels/elements/tet10.hpp"
#include "mesh/mesh.hpp"

#define ARIES_ELEMENT_TYPES(X, ARG)    \
  X(::aries::kernels::Tri3Planar, ARG) \
  X(::aries::kernels::Tri3Cloth, ARG)  \
  X(::aries::kernels::Tet4, ARG)       \
  X(::aries::kernels::Hex8, ARG)       \
  X(::aries::kernels::Tet10, ARG)

// Explicit instantiations of a class template <int R, int C, int NV> for every element type (at the end of the file
// that defines its members).
#define ARIES_INSTANTIATE_CLASS(E, Template) template class Template<E::R, E::C, E::NV>;
#define ARIES_INSTANTIATE_FOR_ELEMENT_TYPES(Template) ARIES_ELEMENT_TYPES(ARIES_INSTANTIATE_CLASS, Template)

namespace aries::fem {

// Whether element type E runs on this mesh: its shape of F (the mesh's dimension and space), its cells' polytope and
// its order (-element).
template <class E>
bool elementFitsMesh(const Mesh &mesh) {
  const int r = mesh.shape == energies::ElementShape::Planar ? 2 : 3;
  const int c = mesh.shape == energies::ElementShape::Tet ? 3 : 2;
  const kernels::CellKind cells = mesh.hexahedra ? kernels::CellKind::Hexahedron
                                  : c == 3      ? kernels::CellKind::Tetrahedron
                                                : kernels::CellKind::Triangle;
  return E::R == r && E::C == c && E::kCells == cells && E::kOrder == (mesh.quadratic ? 2 : 1);
}

}  // namespace aries::fem
