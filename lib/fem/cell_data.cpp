// Cell data: the materials (global and -regions), the dynamics parameters (-density, -gravity), the per-cell
// anisotropy data (uniform from options, per cell from -fiber_file / -fiber2_file), shape targets (-activation,
// -target_file) and the caricature field computed from the rest surface (paper Sec. 6).
#include "fem/discretization_impl.hpp"

#include "fem/caricature_field.hpp"
#include "fem/cell_files.hpp"
#include "core/options.hpp"
#include "fem/fem_options.hpp"

namespace aries::fem {


template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::readMaterials(Mesh &mesh, std::vector<UniformCellData> *regionCells,
                                                    std::vector<std::pair<DMLabel, PetscInt>> *regionLabels) {
  PetscFunctionBeginUser;
  energies::Material base;
  UniformCellData baseCell;
  PetscCall(readMaterialOptions(nullptr, mesh.shape, nullptr, nullptr, &base, &baseCell));
  materials_.push_back(base);
  regionCells->assign(1, baseCell);
  std::vector<std::string> regionIds;
  PetscBool set = PETSC_FALSE;
  PetscCall(core::get(opt::regions, &regionIds, &set));
  for (const auto &rid : regionIds) {
    DMLabel label;
    PetscInt value;
    PetscCall(regionLabel(mesh, rid, &label, &value));
    const std::string prefix = "region_" + rid + "_";
    energies::Material m;
    UniformCellData uc;
    PetscCall(readMaterialOptions(prefix.c_str(), mesh.shape, &base, &baseCell, &m, &uc));
    materials_.push_back(m);
    regionCells->push_back(uc);
    regionLabels->emplace_back(label, value);
  }
  PetscFunctionReturn(0);
}

template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::readDynamics() {
  PetscBool set = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(core::get(opt::density, &dyn_.density, &set));
  std::vector<PetscReal> g;
  PetscCall(core::get(opt::gravity, &g, &set));
  if (R == 3 && g.size() != 3)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -gravity takes 3 comma-separated numbers on a 3D mesh, got %d",
            (int)g.size());
  if (R == 2 && g.size() == 3 && g[2] != 0.0)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -gravity: a 2D mesh takes gx,gy (z must be 0)");
  for (size_t k = 0; k < g.size() && k < static_cast<size_t>(R); ++k) dyn_.gravity[k] = g[k];
  PetscFunctionReturn(0);
}

// Anisotropy data: one shared entry when every cell has the global material's uniform data, else one per cell
// (regions, fiber files, active materials).
template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::setupCellData(Mesh &mesh, const std::vector<UniformCellData> &regionCells,
                                                    bool regions) {
  PetscFunctionBeginUser;
  std::vector<double> fibers, fibers2;
  std::string fiberFile, fiber2File;
  PetscBool hasFiberFile = PETSC_FALSE, hasFiber2File = PETSC_FALSE;
  bool anyFibers = false;
  for (const auto &m : materials_) {
    bool uses = false;
    PetscCall(materialUsesFibers(m.kind, &uses));
    anyFibers = anyFibers || uses;
  }
  if (anyFibers) {
    PetscCall(core::get(opt::fiberFile, &fiberFile, &hasFiberFile));
    if (C == 2 && R == 3) PetscCall(core::get(opt::fiber2File, &fiber2File, &hasFiber2File));
  }
  if (hasFiberFile) PetscCall(readCellVectorFile(comm(), fiberFile, "-fiber_file", mesh.numCellsGlobal, C, &fibers));
  if (hasFiber2File)
    PetscCall(readCellVectorFile(comm(), fiber2File, "-fiber2_file", mesh.numCellsGlobal, C, &fibers2));
  // Active materials carry per-cell data (targets, curvature ratios).
  const bool perCell = regions || hasFiberFile || hasFiber2File || usesEnergy(energies::EnergyKind::ShapeTarget) ||
                       usesEnergy(energies::EnergyKind::Caricature);
  std::vector<energies::CellData<C>> &data = cells_.cellData();
  const size_t nc = cells_.size();
  if (!perCell) {
    data.assign(1, toCellData<C>(regionCells[0]));
  } else {
    data.resize(nc);
    for (size_t c = 0; c < nc; ++c) {
      energies::CellData<C> d = toCellData<C>(regionCells[cells_.cells()[c].region]);
      const size_t nat = static_cast<size_t>(mesh.naturalCell[c]);
      if (hasFiberFile) d.a = Eigen::Map<const kernels::Vec<C>>(&fibers[nat * C]);
      if (hasFiber2File) d.b = Eigen::Map<const kernels::Vec<C>>(&fibers2[nat * C]);
      data[c] = d;
    }
  }
  PetscCall(setupActiveMaterials(mesh));
  restFibers_.resize(nc);
  for (size_t c = 0; c < nc; ++c) {
    const auto &a = cells_.dataOf(c).a;
    restFibers_[c] = {a[0], a[1], C == 3 ? a[C - 1] : 0.0};
  }
  PetscFunctionReturn(0);
}

template <int R, int C>
bool DiscretizationT<R, C>::usesEnergy(energies::EnergyKind kind) const {
  for (const auto &m : materials_)
    if (m.kind == kind) return true;
  return false;
}

// Shape targets that vary over the cells or in time (-activation, -target_file), and the caricature's per-cell
// curvature ratio and normal computed from the rest surface (paper Sec. 6).
template <int R, int C>
PetscErrorCode DiscretizationT<R, C>::setupActiveMaterials(Mesh &mesh) {
  PetscFunctionBeginUser;
  if (usesEnergy(energies::EnergyKind::ShapeTarget)) {
    PetscBool uniform = PETSC_FALSE;
    PetscCall(PetscOptionsHasName(nullptr, nullptr, "-target", &uniform));
    PetscCall(targets_.read(mesh, C, uniform));
    if (targets_.source() != TargetField::Source::Material) updateTargets();
  }
  if (usesEnergy(energies::EnergyKind::Caricature)) {
    if constexpr (R == 3 && C == 3) {
      for (const char *opt : {"-curvature", "-fiber", "-fiber_file"}) {
        PetscBool given = PETSC_FALSE;
        PetscCall(PetscOptionsHasName(nullptr, nullptr, opt, &given));
        if (given)
          SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
                  "option %s does not apply to energy 'caricature' in the solver: each element's curvature ratio c and "
                  "normal n come from the mesh surface (paper Sec. 6); %s is for aries-matpoint",
                  opt, std::string(opt) == "-fiber_file" ? "a uniform -fiber" : opt);
      }
      CaricatureField f;
      PetscCall(computeCaricatureField(mesh, &f));
      auto &data = cells_.cellData();
      for (size_t c = 0; c < cells_.size(); ++c) {
        if (materials_[cells_.cells()[c].region].kind != energies::EnergyKind::Caricature) continue;
        data[c].a = f.normal[c];
        data[c].curvature = f.ratio[c];
      }
      PetscCall(PetscPrintf(comm(),
                            "aries: caricature field: %d surface vertices, mean curvature %.6g, curvature ratio c in "
                            "[%.4g, %.4g]%s\n",
                            (int)f.surfaceVertices, f.meanCurvature, f.minRatio, f.maxRatio,
                            f.degenerateNormals ? " (some cells without a normal: c = 0)" : ""));
    } else {
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "energy 'caricature' needs a tetrahedral mesh");
    }
  }
  PetscFunctionReturn(0);
}

template <int R, int C>
void DiscretizationT<R, C>::updateTargets() {
  auto &data = cells_.cellData();
  for (size_t c = 0; c < cells_.size(); ++c) {
    if (materials_[cells_.cells()[c].region].kind != energies::EnergyKind::ShapeTarget) continue;
    Eigen::Vector3d a = Eigen::Vector3d::Zero();
    a.head<C>() = data[c].a;
    data[c].target = targets_.at(c, step_.time, step_.load, a).template topLeftCorner<C, C>();
  }
}

template class DiscretizationT<3, 3>;
template class DiscretizationT<2, 2>;
template class DiscretizationT<3, 2>;

}  // namespace aries::fem
