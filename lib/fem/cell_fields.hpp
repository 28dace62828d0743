// The per-cell fields an energy takes from the mesh rather than from its options (energies::CellField, named by the
// energy's descriptor). One source per field fills the CellData of the cells whose material names it, at setup and,
// for a field that varies, whenever the step's load or time changes; the discretization knows no field by name.
// A new field: a CellField value, a source class beside its computation, one line in makeCellFieldSource.
#pragma once

#include "energies/material.hpp"
#include "mesh/mesh.hpp"

#include <memory>
#include <vector>

namespace aries::fem {

template <int C>
class CellFieldSource {
 public:
  virtual ~CellFieldSource() = default;
  // Reads or computes the field and writes it into data[c] for every local cell with applies[c]. Collective.
  virtual PetscErrorCode setup(const Mesh &mesh, const std::vector<char> &applies,
                               std::vector<energies::CellData<C>> *data) = 0;
  // Whether the field changes with the step's load or time (then update is called when they change).
  virtual bool varies() const { return false; }
  virtual void update(double /*time*/, double /*load*/, const std::vector<char> & /*applies*/,
                      std::vector<energies::CellData<C>> * /*data*/) const {}
  // A copy for the detached body (the same cells): nothing read or computed again.
  virtual std::unique_ptr<CellFieldSource<C>> clone() const = 0;
};

template <int C>
std::unique_ptr<CellFieldSource<C>> makeCellFieldSource(energies::CellField field);  // cell_fields.cpp
// Every field, in the order they are set up.
inline constexpr energies::CellField kCellFields[] = {energies::CellField::ShapeTargets,
                                                      energies::CellField::SurfaceCurvature};

// The sources of the fields the cells' materials name, with the cells each applies to.
template <int C>
struct CellFields {
  std::vector<std::unique_ptr<CellFieldSource<C>>> sources;
  std::vector<std::vector<char>> applies;  // per source, per local cell
  bool empty() const { return sources.empty(); }
  // One source per field some material names, for the cells of those materials (`regionOf(c)`: the material index of
  // local cell c). Collective.
  template <class RegionOf>
  PetscErrorCode setup(const Mesh &mesh, const std::vector<energies::Material> &materials, size_t numCells,
                       RegionOf regionOf, std::vector<energies::CellData<C>> *data);
  void update(double time, double load, std::vector<energies::CellData<C>> *data) const {
    for (size_t k = 0; k < sources.size(); ++k)
      if (sources[k]->varies()) sources[k]->update(time, load, applies[k], data);
  }
  bool varies() const {
    for (const auto &s : sources)
      if (s->varies()) return true;
    return false;
  }
  CellFields copy() const {
    CellFields out;
    for (const auto &s : sources) out.sources.push_back(s->clone());
    out.applies = applies;
    return out;
  }
};

template <int C>
template <class RegionOf>
PetscErrorCode CellFields<C>::setup(const Mesh &mesh, const std::vector<energies::Material> &materials,
                                    size_t numCells, RegionOf regionOf, std::vector<energies::CellData<C>> *data) {
  PetscFunctionBeginUser;
  for (energies::CellField field : kCellFields) {
    bool named = false;
    for (const auto &m : materials) named = named || energies::energyCellField(m.kind) == field;
    if (!named) continue;
    std::vector<char> mine(numCells, 0);
    for (size_t c = 0; c < numCells; ++c) mine[c] = energies::energyCellField(materials[regionOf(c)].kind) == field;
    sources.push_back(makeCellFieldSource<C>(field));
    PetscCall(sources.back()->setup(mesh, mine, data));
    applies.push_back(std::move(mine));
  }
  PetscFunctionReturn(0);
}

}  // namespace aries::fem
