// The per-cell field sources by field (cell_fields.hpp): one line each.
#include "fem/cell_fields.hpp"

#include "fem/caricature_field.hpp"
#include "fem/shape_targets.hpp"

namespace aries::fem {

template <int C>
std::unique_ptr<CellFieldSource<C>> makeCellFieldSource(energies::CellField field) {
  switch (field) {
    case energies::CellField::ShapeTargets: return makeShapeTargetSource<C>();
    case energies::CellField::SurfaceCurvature: return makeCaricatureSource<C>();
    case energies::CellField::None: break;
  }
  return nullptr;
}

template std::unique_ptr<CellFieldSource<2>> makeCellFieldSource<2>(energies::CellField);
template std::unique_ptr<CellFieldSource<3>> makeCellFieldSource<3>(energies::CellField);

}  // namespace aries::fem
