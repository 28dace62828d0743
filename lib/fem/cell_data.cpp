// Cell data: the per-cell anisotropy data (uniform from the materials' options, per cell from -fiber_file /
// -fiber2_file) and the per-cell fields the materials' energies name (cell_fields.hpp: shape targets, the
// caricature's surface curvature).
#include "fem/discretization_impl.hpp"

#include "mesh/cell_files.hpp"

namespace aries::fem {


// Anisotropy data: one shared entry when every cell has the global material's uniform data, else one per cell
// (regions, fiber files, active materials).
template <int R, int C, int NV>
PetscErrorCode DiscretizationT<R, C, NV>::setupCellData(Mesh &mesh, const FemOptions &o,
                                                    const std::vector<UniformCellData> &regionCells, bool regions) {
  PetscFunctionBeginUser;
  std::vector<double> fibers, fibers2;
  const bool hasFiberFile = !o.fiberFile.empty(), hasFiber2File = !o.fiber2File.empty();
  if (hasFiberFile)  // per local cell
    PetscCall(readCellVectorFile(comm(), o.fiberFile, "-fiber_file", mesh.fileCellCount(), mesh.fileCells(), C,
                                 &fibers));
  if (hasFiber2File)
    PetscCall(readCellVectorFile(comm(), o.fiber2File, "-fiber2_file", mesh.fileCellCount(), mesh.fileCells(), C,
                                 &fibers2));
  // Energies with a per-cell field (targets, curvature ratios) carry per-cell data.
  bool cellField = false;
  for (const auto &m : materials_) cellField = cellField || energies::energyCellField(m.kind) != energies::CellField::None;
  const bool perCell = regions || hasFiberFile || hasFiber2File || cellField;
  std::vector<energies::CellData<C>> &data = cells_.cellData();
  const size_t nc = cells_.size();
  if (!perCell) {
    data.assign(1, toCellData<C>(regionCells[0]));
  } else {
    data.resize(nc);
    for (size_t c = 0; c < nc; ++c) {
      energies::CellData<C> d = toCellData<C>(regionCells[cells_.cells()[c].region]);
      if (hasFiberFile) d.a = Eigen::Map<const kernels::Vec<C>>(&fibers[c * C]);
      if (hasFiber2File) d.b = Eigen::Map<const kernels::Vec<C>>(&fibers2[c * C]);
      data[c] = d;
    }
  }
  PetscCall(fields_.setup(mesh, materials_, nc, [&](size_t c) { return cells_.cells()[c].region; }, &data));
  restFibers_.resize(nc);
  for (size_t c = 0; c < nc; ++c) {
    const auto &a = cells_.dataOf(c).a;
    restFibers_[c] = {a[0], a[1], C == 3 ? a[C - 1] : 0.0};
  }
  PetscFunctionReturn(0);
}

ARIES_INSTANTIATE_FOR_ELEMENT_TYPES(DiscretizationT)

}  // namespace aries::fem
