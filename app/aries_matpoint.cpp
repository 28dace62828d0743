// aries-matpoint: evaluate one material at one deformation gradient, or along a deformation path.
//
//   aries-matpoint -energy NAME -F v1,v2,... [material options] [-json]
//   aries-matpoint -energy NAME -path uniaxial|shear|compress -max X -n N [-shape tet|planar|cloth] [material options]
//
// F has 9 (3x3 tet), 4 (2x2 planar) or 6 (3x2 cloth) entries, row-major. Material options are those of the solver
// (docs/options.md): -E -nu | -mu -lambda, -gamma, -mu1 -mu2, -beta, -fiber, -fiber2, -target, -curvature,
// -singularity and its parameters. Any unknown option is an error.
#include "energies/point_evaluation.hpp"
#include "kernels/dense_decompositions.hpp"
#include "fem/material_options.hpp"
#include "core/options.hpp"
#include "core/errors.hpp"
#include "io/options_help.hpp"
#include "matpoint_options.hpp"

#include <petscsys.h>

#include <cmath>
#include <cstdio>
#include <string>

using namespace aries;
using energies::ElementShape;
using kernels::Mat;
using kernels::Vec;

namespace {

const char kHelp[] =
    "aries-matpoint: evaluate an aries energy at one deformation gradient F or along a deformation path.\n"
    "  aries-matpoint -energy NAME -F v1,... [material options] [-json]\n"
    "  aries-matpoint -energy NAME -path uniaxial|compress|shear [-max X] [-n N] [-shape S] [material options]\n";

// This tool's options, the material options it shares with the solver, and the energies of the registry.
const std::vector<core::OptionSection> &sections() {
  static const std::vector<core::OptionSection> all = [] {
    std::vector<core::OptionSection> s{matpoint::opt::kSection};
    for (const auto &sec : io::optionSections())
      if (std::string(sec.key) == "material" || std::string(sec.key) == "singularity") s.push_back(sec);
    return s;
  }();
  return all;
}

void printHelp() {
  std::printf("%s", kHelp);
  for (const auto &s : sections()) std::printf("%s", io::sectionHelpText(s).c_str());
  std::printf("%s", io::energiesHelpText().c_str());
}

void printNumber(double x) {
  if (std::isfinite(x))
    std::printf("%.17g", x);
  else
    std::printf("null");
}

template <int N>
void printArray(const double *v, int n) {
  std::printf("[");
  for (int i = 0; i < n; ++i) {
    if (i) std::printf(",");
    printNumber(v[i]);
  }
  std::printf("]");
}

template <int R, int C>
PetscErrorCode evaluateAt(const energies::Material &m, const fem::UniformCellData &u, const Mat<R, C> &F, bool json) {
  constexpr int N = R * C;
  PetscFunctionBeginUser;
  const energies::CellData<C> cell = fem::toCellData<C>(u);
  // The PSD projection the solver assembles in dynamic steps (clamp; closed-form eigensystem where the energy has one).
  const energies::HessianFilter clamp{kernels::EigenFilter::Clamp, true};
  const auto point = energies::evaluatePoint<R, C>(m, cell, F, &clamp);
  const auto &d = point.derivs;
  const Mat<N, N> &psd = point.projected;
  const bool hasI4 = point.hasI4, hasI6 = point.hasI6;
  const double I4 = point.I4, I6 = point.I6;
  if (json) {
    Eigen::Matrix<double, N, N, Eigen::RowMajor> H = d.hess, P = psd;
    std::printf("{\"energy\":");
    printNumber(d.value);
    std::printf(",\"pk1\":");
    printArray<N>(d.grad.data(), N);
    std::printf(",\"hessian\":");
    printArray<N>(H.data(), N * N);
    std::printf(",\"hessian_psd\":");
    printArray<N>(P.data(), N * N);
    std::printf(",\"f\":");
    printNumber(point.f);
    std::printf(",\"alpha\":");
    printNumber(point.alpha);
    if (hasI4) {
      std::printf(",\"I4\":");
      printNumber(I4);
    }
    if (hasI6) {
      std::printf(",\"I6\":");
      printNumber(I6);
    }
    std::printf(",\"model\":\"%s\",\"singularity\":\"%s\"}\n", energies::energyName(m.kind),
                energies::singularityName(m.singularity.mode));
  } else {
    std::printf("energy %s (%s elements, singularity %s)\n", energies::energyName(m.kind),
                R == C ? (R == 3 ? "tet" : "planar") : "cloth", energies::singularityName(m.singularity.mode));
    std::printf("  Psi      = %.12g\n", d.value);
    std::printf("  f = I1   = %.12g\n  alpha    = %.12g\n", point.f, point.alpha);
    if (hasI4) std::printf("  I4(a)    = %.12g\n", I4);
    if (hasI6) std::printf("  I6(a,b)  = %.12g\n", I6);
    const Mat<R, C> P = kernels::unflatten<R, C>(d.grad);
    std::printf("  PK1 =\n");
    for (int i = 0; i < R; ++i) {
      std::printf("   ");
      for (int j = 0; j < C; ++j) std::printf(" %14.6e", P(i, j));
      std::printf("\n");
    }
    const kernels::Vec<N> eig = kernels::symmetricEigenvalues<N>(0.5 * (d.hess + d.hess.transpose()));
    std::printf("  Hessian eigenvalues: min %.6e  max %.6e (PSD projection clamps the negative ones)\n", eig[0],
                eig[N - 1]);
  }
  PetscFunctionReturn(0);
}

// F along the path at parameter s (stretch or shear amount); `lateral` holds the relaxed lateral stretches.
template <int R, int C>
Mat<R, C> pathF(const std::string &path, double s, const Vec<C> &lateral) {
  Mat<R, C> F = Mat<R, C>::Identity();
  if (path == "shear") {
    F(0, 1) = s;
  } else {
    F(0, 0) = s;
    for (int k = 1; k < C; ++k) F(k, k) = lateral[k];
  }
  return F;
}

// Newton on the lateral diagonal entries of F so that the lateral nominal stresses vanish (uniaxial stress).
template <int R, int C>
bool relaxLateral(const energies::Material &m, const energies::CellData<C> &cell, double s, Vec<C> &lat) {
  constexpr int L = C - 1;
  for (int it = 0; it < 60; ++it) {
    const auto d = energies::evaluateEnergy<R, C>(m, cell, pathF<R, C>("uniaxial", s, lat));
    Vec<L> g;
    Mat<L, L> H;
    for (int a = 0; a < L; ++a) {
      const int ia = (a + 1) * C + (a + 1);
      g[a] = d.grad[ia];
      for (int b = 0; b < L; ++b) H(a, b) = d.hess(ia, (b + 1) * C + (b + 1));
    }
    if (g.norm() <= 1e-12 * std::max(1.0, d.hess.diagonal().cwiseAbs().maxCoeff())) return true;
    Vec<L> step = H.ldlt().solve(-g);
    if (!step.allFinite() || step.dot(g) >= 0.0) step = -g / (H.diagonal().cwiseAbs().maxCoeff() + 1e-30);
    double t = 1.0;
    for (int k = 0; k < 40; ++k) {
      Vec<C> trial = lat;
      for (int a = 0; a < L; ++a) trial[a + 1] += t * step[a];
      if (trial.tail(L).minCoeff() > 0.0) {
        const auto dt = energies::evaluateEnergy<R, C>(m, cell, pathF<R, C>("uniaxial", s, trial),
                                                       kernels::Order::Gradient);
        Vec<L> gt;
        for (int a = 0; a < L; ++a) gt[a] = dt.grad[(a + 1) * C + (a + 1)];
        if (gt.norm() < g.norm()) {
          lat = trial;
          break;
        }
      }
      t *= 0.5;
    }
  }
  return false;
}

template <int R, int C>
PetscErrorCode runPath(const energies::Material &m, const fem::UniformCellData &u, const std::string &path,
                       double maxAmount, PetscInt n) {
  PetscFunctionBeginUser;
  const energies::CellData<C> cell = fem::toCellData<C>(u);
  std::printf("strain");
  for (int k = 0; k < C; ++k) std::printf(",F%d%d", k + 1, k + 1);
  std::printf(",F12,energy");
  for (int k = 0; k < C; ++k) std::printf(",P%d%d", k + 1, k + 1);
  std::printf(",P12,alpha,lateral_converged\n");
  Vec<C> lat = Vec<C>::Ones();
  for (PetscInt i = 0; i <= n; ++i) {
    const double frac = static_cast<double>(i) / static_cast<double>(n);
    double s, strain;
    if (path == "shear") {
      s = strain = frac * maxAmount;
    } else {
      strain = (path == "compress" ? -1.0 : 1.0) * frac * maxAmount;
      s = 1.0 + strain;
    }
    bool ok = true;
    if (path != "shear") ok = relaxLateral<R, C>(m, cell, s, lat);
    const Mat<R, C> F = pathF<R, C>(path, s, lat);
    const auto d = energies::evaluateEnergy<R, C>(m, cell, F, kernels::Order::Gradient);
    std::printf("%.10g", strain);
    for (int k = 0; k < C; ++k) std::printf(",%.12g", F(k, k));
    std::printf(",%.12g,%.12g", F(0, 1), d.value);
    for (int k = 0; k < C; ++k) std::printf(",%.12g", d.grad[k * C + k]);
    std::printf(",%.12g,%.12g,%d\n", d.grad[1], energies::elementAlpha<R, C>(F), ok ? 1 : 0);
  }
  PetscFunctionReturn(0);
}

PetscErrorCode run() {
  PetscBool json = PETSC_FALSE;
  PetscFunctionBeginUser;
  PetscCall(core::get(matpoint::opt::json, &json));
  std::vector<PetscReal> Fv;
  PetscBool hasF = PETSC_FALSE, hasPath = PETSC_FALSE;
  PetscCall(core::get(matpoint::opt::F, &Fv, &hasF));
  int path = 0;  // uniaxial|compress|shear
  PetscCall(core::getChoice(matpoint::opt::path, &path, &hasPath));
  if (hasF == hasPath)
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
            "give either -F v1,v2,... (9, 4 or 6 values) or -path uniaxial|shear|compress (see -help)");
  const std::string pathName = core::choices(matpoint::opt::path)[path];

  ElementShape shape = ElementShape::Tet;
  if (hasF) {
    if (Fv.size() == 9) shape = ElementShape::Tet;
    else if (Fv.size() == 4) shape = ElementShape::Planar;
    else if (Fv.size() == 6) shape = ElementShape::Cloth;
    else
      SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT,
              "option -F takes 9 (3x3 tet), 4 (2x2 planar) or 6 (3x2 cloth) row-major values, got %d", (int)Fv.size());
  } else {
    int s = 0;  // tet|planar|cloth
    PetscCall(core::getChoice(matpoint::opt::shape, &s));
    shape = s == 0 ? ElementShape::Tet : s == 1 ? ElementShape::Planar : ElementShape::Cloth;
  }

  energies::Material m;
  fem::UniformCellData cell;
  PetscCall(fem::readMaterialOptions(nullptr, shape, nullptr, nullptr, false, &m, &cell));

  if (hasF) {
    PetscCall(core::rejectUnusedOptions());
    if (shape == ElementShape::Tet) PetscCall(evaluateAt<3, 3>(m, cell, kernels::unflatten<3, 3>(Vec<9>(Fv.data())), json));
    if (shape == ElementShape::Planar) PetscCall(evaluateAt<2, 2>(m, cell, kernels::unflatten<2, 2>(Vec<4>(Fv.data())), json));
    if (shape == ElementShape::Cloth) PetscCall(evaluateAt<3, 2>(m, cell, kernels::unflatten<3, 2>(Vec<6>(Fv.data())), json));
    PetscFunctionReturn(0);
  }
  PetscReal maxAmount = 0.0;
  PetscInt n = 0;
  PetscCall(core::get(matpoint::opt::maxAmount, &maxAmount));
  PetscCall(core::get(matpoint::opt::points, &n));
  if (pathName == "compress" && !(maxAmount < 1.0))
    SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "option -max: compression must be < 1 (got %g)", (double)maxAmount);
  if (json) SETERRQ(PETSC_COMM_SELF, PETSC_ERR_USER_INPUT, "-json applies to -F evaluations; -path prints CSV");
  PetscCall(core::rejectUnusedOptions());
  if (shape == ElementShape::Tet) PetscCall(runPath<3, 3>(m, cell, pathName, maxAmount, n));
  if (shape == ElementShape::Planar) PetscCall(runPath<2, 2>(m, cell, pathName, maxAmount, n));
  if (shape == ElementShape::Cloth) PetscCall(runPath<3, 2>(m, cell, pathName, maxAmount, n));
  PetscFunctionReturn(0);
}

}  // namespace

int main(int argc, char **argv) {
  for (int i = 1; i < argc; ++i)
    if (std::string(argv[i]) == "-help" || std::string(argv[i]) == "--help" || std::string(argv[i]) == "-h") {
      printHelp();  // this tool's help only (PETSc's generic option list does not apply here)
      return 0;
    }
  PetscErrorCode ierr = PetscInitialize(&argc, &argv, nullptr, nullptr);
  if (ierr) return 2;
  ierr = core::installErrorHandler("aries-matpoint");
  core::registerOptionSections(sections().data(), static_cast<int>(sections().size()));
  if (!ierr) ierr = run();
  const int code = core::exitCodeFor(ierr);
  PetscOptionsClear(nullptr);  // unused options were already reported; keep PetscFinalize quiet
  PetscFinalize();
  return code;
}
