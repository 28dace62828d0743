// Kernel benchmark: nanoseconds per element for energy + PK1 + Hessian (optionally + PSD projection of the 9x9
// F-space Hessian) of the closed-form energies against their SVD-based counterparts, on 3x3 F (tetrahedra).
//
// Every benchmark iteration evaluates ONE element, cycling through a fixed pool of 4096 deformation gradients, so
// the reported time per iteration is the time per element (also printed as the counter "t/elem"). Two pools:
//   sim  : F = R (I + 0.1 G), R a uniformly random rotation, G with i.i.d. N(0,1) entries (typical simulation F)
//   hard : F with i.i.d. N(0,1) entries (generic, about half of them inverted, some near the singular set)
// Row names are "<kernel>/<pool>"; bench/README.md explains each row.
//
// Before timing, the closed-form and SVD-based alx (and iarap vs arap_svd) are checked to agree on a few F of each
// pool; the program aborts if they do not.
#include "energies/energy.hpp"
#include "energies/material.hpp"
#include "kernels/alpha.hpp"
#include "kernels/fiber_invariants.hpp"
#include "kernels/psd_projection.hpp"
#include "kernels/root_function.hpp"
#include "kernels/stretch_invariants.hpp"
#include "kernels/svd_polar.hpp"

#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <functional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace en = aries::energies;
namespace kn = aries::kernels;
using Mat3 = Eigen::Matrix3d;
using Mat9 = kn::Mat<9, 9>;
using D9 = kn::Derivs<9>;
using kn::Order;

constexpr std::size_t kPoolSize = 4096;  // power of two: the index wraps with a mask
static_assert((kPoolSize & (kPoolSize - 1)) == 0, "pool size must be a power of two");

struct Pool {
  std::string name;
  std::vector<Mat3> F;
  std::vector<Mat9> H;  // closed-form iarap Hessians of F (input of the projectToPSD micro-benchmark)
};

Mat3 randomRotation(std::mt19937_64 &rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  Eigen::Vector4d q;
  for (int k = 0; k < 4; ++k) q[k] = n01(rng);
  return kn::quaternionToRotation(q.normalized());
}

Mat3 gaussianMatrix(std::mt19937_64 &rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  Mat3 G;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) G(i, j) = n01(rng);
  return G;
}

Pool makePool(const std::string &name, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  Pool p;
  p.name = name;
  p.F.reserve(kPoolSize);
  for (std::size_t e = 0; e < kPoolSize; ++e) {
    if (name == "sim")
      p.F.push_back(randomRotation(rng) * (Mat3::Identity() + 0.1 * gaussianMatrix(rng)));
    else
      p.F.push_back(gaussianMatrix(rng));
  }
  return p;
}

// ---- materials ----------------------------------------------------------------------------------------------------
constexpr double kMu = 1.0;
constexpr double kLambda = 1.5;  // nu = 0.3 with mu = 1: the volume term lambda/2 (J-1)^2 is on for iarap & arap_svd

en::Material makeMaterial(en::EnergyKind kind, en::SingularityMode mode, double lambda) {
  en::Material m;
  m.kind = kind;
  m.mu = kMu;
  m.lambda = lambda;
  m.singularity.mode = mode;
  const std::string err = en::finalizeMaterial(m, en::ElementShape::Tet);
  if (!err.empty()) {
    std::fprintf(stderr, "kernel_bench: finalizeMaterial failed: %s\n", err.c_str());
    std::abort();
  }
  return m;
}

const Eigen::Vector3d kFiber = Eigen::Vector3d(1.0, 2.0, 3.0).normalized();  // fixed unit fiber for alx

// SVD-based alx: mu/2 (I5 - 2 I4 + 1) with I4 (value, PK1, Hessian) from the signed-SVD polar perturbation.
D9 svdAlx(const Mat3 &F, const Eigen::Vector3d &a, double mu) {
  const Mat3 A = kn::fiberTensor<3>(a);
  D9 out = kn::invariantI5<3, 3>(F, a, Order::Hessian);
  out += kn::svdStretchInvariant<3>(F, A, Order::Hessian).scale(-2.0);
  out.value += 1.0;
  return out.scale(0.5 * mu);
}

// ---- prototypes (bench-only, NOT used by the solver) -----------------------------------------------------------------
// Evidence for kernel optimizations: what the closed-form iarap costs when assembled in one pass.
// For W = mu I, tr(S W) = mu I1 = mu f, so the iarap shear term is mu (I_C - 2 f + 3) and its Hessian is
//   2 mu I - 2 mu dR/dF,  dR/dF = 2 f_1 I + f_2 H(II_C) + f_J H(J) + G d2f G^T,  G = [2F, 4FC, cof F]
// (Eq. 19 with only first/second root derivatives). The volume term adds lambda (g_J g_J^T + (J-1) H(J)), so the
// whole Hessian is  a I + c2 H(II_C) + cJ H(J) + G D G^T  with one 3x3 middle matrix D. Valid outside the mollifier
// band (alpha > 3 eps), i.e. everywhere on both pools (checked before timing).
D9 fusedIarap(const Mat3 &F, double mu, double lambda) {
  const kn::RootDerivatives<3> rd = kn::rootDerivatives(F, 2);
  const double f = rd.root.f, f1 = rd.d1[0], f2 = rd.d1[1], fJ = rd.d1[2];
  const Mat3 Cg = F.transpose() * F;
  const Mat3 B = F * F.transpose();
  const Mat3 FC = F * Cg;
  const Mat3 cof = kn::cofactor(F);
  const double J = F.determinant(), IC = Cg.trace();
  const Mat3 R = 2.0 * f1 * F + 4.0 * f2 * FC + fJ * cof;
  D9 out;
  out.value = mu * (IC - 2.0 * f + 3.0) + 0.5 * lambda * (J - 1.0) * (J - 1.0);
  out.grad = kn::flatten<3, 3>(Mat3(2.0 * mu * (F - R) + lambda * (J - 1.0) * cof));
  const double a = 2.0 * mu - 4.0 * mu * f1;
  const double c2 = -2.0 * mu * f2 * 4.0;  // H(II_C) = 4 (d_ik C_lj + F_il F_kj + B_ik d_jl)
  const double cJ = -2.0 * mu * fJ + lambda * (J - 1.0);
  Mat9 &H = out.hess;
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      const int l = 3 - i - k;
      const double s = (i == k) ? 0.0 : (((k - i + 3) % 3 == 1) ? cJ : -cJ);
      const double a0 = (i == k) ? 0.0 : F(l, 0), a1 = (i == k) ? 0.0 : F(l, 1), a2 = (i == k) ? 0.0 : F(l, 2);
      const double blk[3][3] = {{0.0, a2, -a1}, {-a2, 0.0, a0}, {a1, -a0, 0.0}};
      for (int j = 0; j < 3; ++j)
        for (int m = 0; m < 3; ++m) {
          double h = F(i, m) * F(k, j);
          if (i == k) h += Cg(m, j);
          if (j == m) h += B(i, k);
          H(i * 3 + j, k * 3 + m) = c2 * h + s * blk[j][m] + ((i == k && j == m) ? a : 0.0);
        }
    }
  kn::Mat<9, 3> G;
  G.col(0) = kn::flatten<3, 3>(Mat3(2.0 * F));
  G.col(1) = kn::flatten<3, 3>(Mat3(4.0 * FC));
  G.col(2) = kn::flatten<3, 3>(cof);
  Mat3 D = -2.0 * mu * rd.d2;
  D(2, 2) += lambda;
  const kn::Mat<9, 3> GD = G * D;
  H.noalias() += GD * G.transpose();
  return out;
}

// PSD projection that first tries a Cholesky factorization and only runs the 9x9 eigensolver when it fails.
Mat9 projectToPSDCholeskyFirst(const Mat9 &H) {
  const Mat9 Hs = 0.5 * (H + H.transpose());
  Eigen::LLT<Mat9> llt(Hs);
  if (llt.info() == Eigen::Success) return Hs;
  return kn::projectToPSD<9>(Hs);
}

// ---- correctness gate -----------------------------------------------------------------------------------------------
double normalizedAlpha(const Mat3 &F) {
  const double s = F.norm();
  return kn::rootValue(F).alpha / (s * s * s);
}

bool agree(const D9 &x, const D9 &y, double tol, const char *what, const std::string &pool, std::size_t e) {
  const double dv = std::abs(x.value - y.value) / (1.0 + std::abs(y.value));
  const double dg = (x.grad - y.grad).norm() / (1.0 + y.grad.norm());
  const double dh = (x.hess - y.hess).norm() / (1.0 + y.hess.norm());
  if (dv <= tol && dg <= tol && dh <= tol) return true;
  std::fprintf(stderr, "kernel_bench: %s mismatch on pool %s element %zu: rel. value %.3e, PK1 %.3e, Hessian %.3e\n",
               what, pool.c_str(), e, dv, dg, dh);
  return false;
}

// Closed-form vs SVD on the first 16 elements of each pool that are clearly away from the singular set (normalized
// alpha > 0.1; the mollifier is then inactive and the two formulations are the same function of F).
void checkAgreement(const std::vector<Pool> &pools) {
  const en::Material alx = makeMaterial(en::EnergyKind::Alx, en::SingularityMode::Mollifier, 0.0);
  const en::Material iarap = makeMaterial(en::EnergyKind::Iarap, en::SingularityMode::Mollifier, kLambda);
  const en::Material arapSvd = makeMaterial(en::EnergyKind::ArapSvd, en::SingularityMode::None, kLambda);
  en::CellData<3> cell;
  cell.a = kFiber;
  bool ok = true;
  for (const Pool &p : pools) {
    int checked = 0;
    for (std::size_t e = 0; e < p.F.size() && checked < 16; ++e) {
      const Mat3 &F = p.F[e];
      if (!(normalizedAlpha(F) > 0.1)) continue;
      ok &= agree(en::evaluateEnergy<3, 3>(alx, cell, F), svdAlx(F, kFiber, kMu), 1e-7, "alx closed-form vs SVD",
                  p.name, e);
      ok &= agree(en::evaluateEnergy<3, 3>(iarap, cell, F), en::evaluateEnergy<3, 3>(arapSvd, cell, F), 1e-7,
                  "iarap closed-form vs arap_svd", p.name, e);
      ++checked;
    }
    // The bench-only fused prototype must reproduce the library's iarap on every timed element (outside the
    // mollifier band and Horn's eigen path, where it does not apply; both pools have no such element).
    for (std::size_t e = 0; e < p.F.size(); ++e) {
      const kn::RootValue r = kn::rootValue(p.F[e]);
      if (r.fromEigen || r.alpha <= 3.0 * iarap.singularity.mollifier.eps) continue;
      ok &= agree(fusedIarap(p.F[e], kMu, kLambda), en::evaluateEnergy<3, 3>(iarap, cell, p.F[e]), 1e-6,
                  "prototype fused iarap vs iarap", p.name, e);
    }
    if (checked < 16) {
      std::fprintf(stderr, "kernel_bench: pool %s has only %d well-conditioned elements\n", p.name.c_str(), checked);
      ok = false;
    }
  }
  if (!ok) {
    std::fprintf(stderr, "kernel_bench: closed-form and SVD kernels disagree; refusing to time them\n");
    std::abort();
  }
  std::fprintf(stderr,
               "kernel_bench: closed-form alx == SVD alx and iarap == arap_svd on 16 F per pool (rel. 1e-7); "
               "proto:iarap_fused == iarap on every pool element (rel. 1e-6)\n");
}

// Pool statistics, recorded in the benchmark context (JSON "context") so the report can quote them.
void describePool(const Pool &p) {
  std::size_t inverted = 0, horn = 0, belowEps = 0, band = 0, posdef = 0;
  for (const Mat9 &H : p.H) posdef += Eigen::LLT<Mat9>(H).info() == Eigen::Success;
  for (const Mat3 &F : p.F) {
    const kn::RootValue r = kn::rootValue(F);
    inverted += F.determinant() < 0.0;
    horn += r.fromEigen;
    belowEps += r.alpha < 1e-3;
    band += (r.alpha >= 1e-3 && r.alpha <= 3e-3);
  }
  std::ostringstream s;
  s << "n=" << p.F.size() << " inverted=" << inverted << " horn_eigen_path=" << horn << " alpha<eps=" << belowEps
    << " mollifier_band=" << band << " iarap_hessian_posdef=" << posdef;
  benchmark::AddCustomContext("pool_" + p.name, s.str());
  std::fprintf(stderr, "kernel_bench: pool %s: %s\n", p.name.c_str(), s.str().c_str());
}

// ---- timing harness -----------------------------------------------------------------------------------------------
// One element per iteration; the result object is forced to memory so no part of it can be dropped.
template <class T, class Fn>
void runOverPool(benchmark::State &state, const std::vector<T> &items, Fn fn) {
  std::size_t i = 0;
  for (auto _ : state) {
    auto r = fn(items[i]);
    benchmark::DoNotOptimize(r);
    benchmark::ClobberMemory();
    i = (i + 1) & (kPoolSize - 1);
  }
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations()));
  // kIsRate divides by the CPU time, kInvert flips it: CPU seconds per element (printed as e.g. "1.23us").
  state.counters["t/elem"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

template <class Fn>
void addF(const std::string &kernel, const Pool &pool, Fn fn) {
  const std::string name = kernel + "/" + pool.name;
  benchmark::RegisterBenchmark(name.c_str(), [&pool, fn](benchmark::State &st) { runOverPool(st, pool.F, fn); });
}

// Energy + PK1 + Hessian, and the same followed by the PSD projection of the 9x9 Hessian.
template <class Fn>
void addEnergy(const std::string &kernel, const Pool &pool, Fn fn) {
  addF(kernel, pool, fn);
  addF(kernel + "+psd", pool, [fn](const Mat3 &F) {
    D9 d = fn(F);
    d.hess = kn::projectToPSD<9>(d.hess);
    return d;
  });
}

void registerAll(const std::vector<Pool> &pools) {
  static const en::Material iarap = makeMaterial(en::EnergyKind::Iarap, en::SingularityMode::Mollifier, kLambda);
  static const en::Material iarapNone = makeMaterial(en::EnergyKind::Iarap, en::SingularityMode::None, kLambda);
  static const en::Material iarapLin = makeMaterial(en::EnergyKind::IarapLin, en::SingularityMode::None, kLambda);
  static const en::Material arapSvd = makeMaterial(en::EnergyKind::ArapSvd, en::SingularityMode::None, kLambda);
  static const en::Material alx = makeMaterial(en::EnergyKind::Alx, en::SingularityMode::Mollifier, 0.0);
  static const en::Material alxNone = makeMaterial(en::EnergyKind::Alx, en::SingularityMode::None, 0.0);
  static en::CellData<3> cell;
  cell.a = kFiber;
  static const Mat3 W = iarap.weight3;  // mu I
  static const Mat3 A = kn::fiberTensor<3>(kFiber);

  for (const Pool &p : pools) {
    auto energy = [](const en::Material &m) {
      return [&m](const Mat3 &F) { return en::evaluateEnergy<3, 3>(m, cell, F, Order::Hessian); };
    };
    // (a)-(g): the energies, each without and with PSD projection.
    addEnergy("iarap", p, energy(iarap));                 // closed form, default singularity mode (mollifier)
    addEnergy("iarap[sing=none]", p, energy(iarapNone));  // closed form, no mollifier (no alpha derivatives)
    addEnergy("arap_svd", p, energy(arapSvd));
    addEnergy("iarap_lin", p, energy(iarapLin));
    addEnergy("alx", p, energy(alx));
    addEnergy("alx[sing=none]", p, energy(alxNone));
    addEnergy("alx_svd", p, [](const Mat3 &F) { return svdAlx(F, kFiber, kMu); });

    // Micro-benchmarks for context.
    addF("micro:rootValue", p, [](const Mat3 &F) { return kn::rootValue(F); });
    addF("micro:signedSvd", p, [](const Mat3 &F) { return kn::signedSvd<3>(F); });
    benchmark::RegisterBenchmark(("micro:projectToPSD<9>/" + p.name).c_str(), [&p](benchmark::State &st) {
      runOverPool(st, p.H, [](const Mat9 &H) { return kn::projectToPSD<9>(H); });
    });

    // Cumulative breakdown of the closed-form iarap (each row includes the previous one).
    addF("parts:iarap.1_ctx", p, [](const Mat3 &F) { return kn::makeRootContext<3, 3>(F, Order::Hessian); });
    addF("parts:iarap.2_ctx+alpha", p, [](const Mat3 &F) {
      const auto ctx = kn::makeRootContext<3, 3>(F, Order::Hessian);
      return kn::alphaMeasure(ctx);
    });
    addF("parts:iarap.3_ctx+alpha+trSW", p, [](const Mat3 &F) {
      const auto ctx = kn::makeRootContext<3, 3>(F, Order::Hessian);
      D9 a = kn::alphaMeasure(ctx);
      a += kn::stretchInvariant<3, 3>(ctx, W);
      return a;
    });
    addF("parts:iarap.ctx+trSW", p, [](const Mat3 &F) {
      const auto ctx = kn::makeRootContext<3, 3>(F, Order::Hessian);
      return kn::stretchInvariant<3, 3>(ctx, W);
    });
    addF("parts:iarap.ctx+I1", p, [](const Mat3 &F) {
      const auto ctx = kn::makeRootContext<3, 3>(F, Order::Hessian);
      return kn::invariantI1<3, 3>(ctx);
    });
    // Breakdown of arap_svd.
    addF("parts:arap_svd.svd+R", p, [](const Mat3 &F) {
      const auto s = kn::signedSvd<3>(F);
      return kn::svdRotation<3>(s);
    });
    addF("parts:arap_svd.svd+R+dRdF", p, [](const Mat3 &F) {
      const auto s = kn::signedSvd<3>(F);
      return std::make_pair(kn::svdRotation<3>(s), kn::svdRotationGradient<3>(s));
    });
    // Prototypes (bench-only): one-pass closed-form iarap; Cholesky-first PSD; 3x3 symmetric eigensolve (the core of
    // an analytic projection of the ARAP twist modes, whose eigenvectors are R [v_k]_x with v_k eigenvectors of S).
    addEnergy("proto:iarap_fused", p, [](const Mat3 &F) { return fusedIarap(F, kMu, kLambda); });
    benchmark::RegisterBenchmark(("proto:projectToPSD_cholesky_first/" + p.name).c_str(), [&p](benchmark::State &st) {
      runOverPool(st, p.H, [](const Mat9 &H) { return projectToPSDCholeskyFirst(H); });
    });
    addF("proto:eig3x3_direct(S)", p, [](const Mat3 &F) {
      const Mat3 R = kn::analyticRotation<3, 3>(F);
      const Mat3 S = R.transpose() * F;
      Eigen::SelfAdjointEigenSolver<Mat3> eig;
      eig.computeDirect(0.5 * (S + S.transpose()));
      return std::make_pair(Mat3(eig.eigenvectors()), Eigen::Vector3d(eig.eigenvalues()));
    });
    // The SVD-based I4 alone (alx_svd minus the trivial I5 term).
    addF("parts:alx_svd.svdStretchInvariant", p,
         [](const Mat3 &F) { return kn::svdStretchInvariant<3>(F, A, Order::Hessian); });
  }
}

}  // namespace

int main(int argc, char **argv) {
  static std::vector<Pool> pools = {makePool("sim", 20240601), makePool("hard", 20240602)};
  {
    const en::Material iarap = makeMaterial(en::EnergyKind::Iarap, en::SingularityMode::Mollifier, kLambda);
    en::CellData<3> cell;
    for (Pool &p : pools) {
      p.H.reserve(p.F.size());
      for (const Mat3 &F : p.F) p.H.push_back(en::evaluateEnergy<3, 3>(iarap, cell, F).hess);
    }
  }
  checkAgreement(pools);
  for (const Pool &p : pools) describePool(p);
  benchmark::AddCustomContext("pool_size", std::to_string(kPoolSize));
  registerAll(pools);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
