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
               "kernel_bench: closed-form alx == SVD alx and iarap == arap_svd on 16 F per pool (rel. 1e-7)\n");
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

// Energy + PK1 + Hessian, and the same followed by the numeric PSD projection of the 9x9 Hessian (the SVD baselines).
template <class Fn>
void addEnergy(const std::string &kernel, const Pool &pool, Fn fn) {
  addF(kernel, pool, fn);
  addF(kernel + "+psd", pool, [fn](const Mat3 &F) {
    D9 d = fn(F);
    d.hess = kn::projectToPSD<9>(d.hess);
    return d;
  });
}

// A material's energy as the assembly evaluates it: `+psd` is the solver's path (evaluateFilteredEnergy, clamp,
// through the energy's closed-form eigensystem where it has one), `+psd[numeric]` the numeric 9x9 projection
// (-psd_eigensystem numeric).
void addMaterialEnergy(const std::string &kernel, const Pool &pool, const en::Material &m, const en::CellData<3> &cell) {
  addF(kernel, pool, [&m, &cell](const Mat3 &F) { return en::evaluateEnergy<3, 3>(m, cell, F, Order::Hessian); });
  addF(kernel + "+psd", pool, [&m, &cell](const Mat3 &F) {
    return en::evaluateFilteredEnergy<3, 3>(m, cell, F, en::HessianFilter{kn::EigenFilter::Clamp, true});
  });
  addF(kernel + "+psd[numeric]", pool, [&m, &cell](const Mat3 &F) {
    return en::evaluateFilteredEnergy<3, 3>(m, cell, F, en::HessianFilter{kn::EigenFilter::Clamp, false});
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
  static const Mat3 A = kn::fiberTensor<3>(kFiber);

  for (const Pool &p : pools) {
    // (a)-(g): the energies, each without and with PSD projection.
    addMaterialEnergy("iarap", p, iarap, cell);                 // closed form, default singularity mode (mollifier)
    addMaterialEnergy("iarap[sing=none]", p, iarapNone, cell);  // closed form, no mollifier (no alpha derivatives)
    addEnergy("arap_svd", p, [](const Mat3 &F) { return en::evaluateEnergy<3, 3>(arapSvd, cell, F, Order::Hessian); });
    addMaterialEnergy("iarap_lin", p, iarapLin, cell);
    addMaterialEnergy("alx", p, alx, cell);
    addMaterialEnergy("alx[sing=none]", p, alxNone, cell);
    addEnergy("alx_svd", p, [](const Mat3 &F) { return svdAlx(F, kFiber, kMu); });

    // Micro-benchmarks for context.
    addF("micro:rootValue", p, [](const Mat3 &F) { return kn::rootValue(F); });
    addF("micro:signedSvd", p, [](const Mat3 &F) { return kn::signedSvd<3>(F); });
    benchmark::RegisterBenchmark(("micro:projectToPSD<9>/" + p.name).c_str(), [&p](benchmark::State &st) {
      runOverPool(st, p.H, [](const Mat9 &H) { return kn::projectToPSD<9>(H); });
    });

    // iarap's general (unfused) path: the same energy as ortho with equal moduli, evaluated through the root
    // context, the invariant Hessians and the chain rule instead of the fused tet kernel.
    addF("parts:iarap.general_path", p, [](const Mat3 &F) {
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
