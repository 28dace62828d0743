// One material point of the fiber energy (iarap + gamma/2 (I4(a) - 1)^2, TOG 2024 Sec. 6) through the installed
// aries kernels: energy, PK1 and the projected (clamped) Hessian at one F, printed as JSON in aries-matpoint -json's
// orderings (row-major F and PK1; the Hessian in that vec order).
#include <energies/energy.hpp>

#include <cstdio>

int main() {
  using namespace aries;
  energies::Material material;
  material.kind = energies::EnergyKind::Fiber;
  material.mu = energies::lameMu(1e4, 0.3);  // E = 1e4, nu = 0.3
  material.lambda = energies::lameLambda(1e4, 0.3);
  material.gamma = 50.0;
  const std::string problem = energies::finalizeMaterial(material, energies::ElementShape::Tet);
  if (!problem.empty()) {
    std::fprintf(stderr, "fiber_point: error: %s\n", problem.c_str());
    return 1;
  }
  energies::CellData<3> cell;
  cell.a = Eigen::Vector3d(1, 1, 0).normalized();  // the fiber, a unit vector in the material frame

  kernels::Mat<3, 3> F;
  F << 1.1, 0.2, 0.0, -0.1, 0.9, 0.05, 0.0, 0.3, 1.2;
  const auto d = energies::evaluateEnergy<3, 3>(material, cell, F);
  const auto psd = energies::evaluateFilteredEnergy<3, 3>(material, cell, F, {kernels::EigenFilter::Clamp, true});

  std::printf("{\"energy\":%.17g,\"pk1\":[", d.value);
  for (int k = 0; k < 9; ++k) std::printf("%s%.17g", k ? "," : "", d.grad[k]);
  std::printf("],\"hessian_psd\":[");
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) std::printf("%s%.17g", i + j ? "," : "", psd.hess(i, j));
  std::printf("]}\n");
  return 0;
}
