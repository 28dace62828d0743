// Finite-difference tests of PK1 and Hessian for every invariant kernel:
//   I_C, II_C, J, III_C, IV_C / V_C / I_8 / VI_C for D = aa^T and for the cross tensor (ab^T + ba^T)/2, I5, I7,
//   I1 (= f, gradient R), I2, I3, I4, I6 and alpha,
// for 3x3 (tet), 2x2 (planar) and 3x2 (cloth) F over the standard families of test_support.hpp (random, inverted,
// stretched/compressed, near alpha = 0 at normalized alpha 0.1 and 0.02). The mollified invariants and the barrier
// are FD-tested in test_singularity_fixes.cpp with F placed inside their active bands.
#include "kernels/alpha.hpp"
#include "kernels/fiber_invariants.hpp"
#include "kernels/stretch_invariants.hpp"
#include "test_support.hpp"

namespace aries::test {
namespace {

using namespace aries::kernels;

template <int C>
struct Fibers {
  Vec<C> a, b;  // random unit fibers, b NOT orthogonal to a (the general cross-fiber case)
};

// Runs the FD check of `fn(F, order, fibers)` over all standard families; each family sample gets its own fibers.
template <int R, int C, class Fn>
void runInvariant(const std::string &name, Fn &&fn, FdExpect ex = {}) {
  const auto samples = standardFamilies<R, C>(seedOf(name));
  Rng rng(seedOf(name) + 1);
  int checked = 0;
  for (const auto &s : samples) {
    const Fibers<C> fb{randomUnit<C>(rng), randomUnit<C>(rng)};
    auto bound = [&](const Mat<R, C> &F, Order o) { return fn(F, o, fb); };
    expectDerivatives<R, C>(bound, s.F, name + " " + shapeTag<R, C>() + " on " + s.label,
                            name + " " + shapeTag<R, C>() + " " + s.family, ex);
    ++checked;
  }
  EXPECT_GE(checked, 6);
}

#define ARIES_FD_INVARIANT(Name, R_, C_, ...)                                                              \
  TEST(InvariantFD, Name##_##R_##x##C_) {                                                                  \
    constexpr int R = R_, C = C_;                                                                          \
    runInvariant<R, C>(#Name, [](const Mat<R, C> &F, Order o, const Fibers<C> &fb) -> Derivs<R * C> {     \
      (void)fb;                                                                                            \
      return __VA_ARGS__;                                                                                  \
    });                                                                                                    \
  }
#define ARIES_FD_INVARIANT_ALL_SHAPES(Name, ...) \
  ARIES_FD_INVARIANT(Name, 3, 3, __VA_ARGS__)    \
  ARIES_FD_INVARIANT(Name, 2, 2, __VA_ARGS__)    \
  ARIES_FD_INVARIANT(Name, 3, 2, __VA_ARGS__)

// Cauchy-Green invariants.
ARIES_FD_INVARIANT_ALL_SHAPES(IC, invariantIC<R, C>(F, o))
ARIES_FD_INVARIANT_ALL_SHAPES(IIC, invariantIIC<R, C>(F, o))
ARIES_FD_INVARIANT(J, 3, 3, invariantJ(F, o))
ARIES_FD_INVARIANT(J, 2, 2, invariantJ(F, o))
ARIES_FD_INVARIANT(IIIC, 2, 2, invariantIIIC<2>(F, o))
ARIES_FD_INVARIANT(IIIC, 3, 2, invariantIIIC<3>(F, o))

// Fiber invariants for D = aa^T ...
ARIES_FD_INVARIANT_ALL_SHAPES(IVC_fiber, invariantIVC<R, C>(F, fiberTensor<C>(fb.a), o))
ARIES_FD_INVARIANT_ALL_SHAPES(VC_fiber, invariantVC<R, C>(F, fiberTensor<C>(fb.a), o))
ARIES_FD_INVARIANT(I8_fiber, 3, 3, invariantI8<3>(F, fiberTensor<3>(fb.a), o))
ARIES_FD_INVARIANT(I8_fiber, 2, 2, invariantI8<2>(F, fiberTensor<2>(fb.a), o))
ARIES_FD_INVARIANT(VIC_fiber, 2, 2, invariantVIC<2>(F, fiberTensor<2>(fb.a), o))
ARIES_FD_INVARIANT(VIC_fiber, 3, 2, invariantVIC<3>(F, fiberTensor<2>(fb.a), o))
// ... and for the cross tensor (ab^T + ba^T)/2.
ARIES_FD_INVARIANT_ALL_SHAPES(IVC_cross, invariantIVC<R, C>(F, crossFiberTensor<C>(fb.a, fb.b), o))
ARIES_FD_INVARIANT_ALL_SHAPES(VC_cross, invariantVC<R, C>(F, crossFiberTensor<C>(fb.a, fb.b), o))
ARIES_FD_INVARIANT(I8_cross, 3, 3, invariantI8<3>(F, crossFiberTensor<3>(fb.a, fb.b), o))
ARIES_FD_INVARIANT(I8_cross, 2, 2, invariantI8<2>(F, crossFiberTensor<2>(fb.a, fb.b), o))
ARIES_FD_INVARIANT(VIC_cross, 2, 2, invariantVIC<2>(F, crossFiberTensor<2>(fb.a, fb.b), o))
ARIES_FD_INVARIANT(VIC_cross, 3, 2, invariantVIC<3>(F, crossFiberTensor<2>(fb.a, fb.b), o))
ARIES_FD_INVARIANT_ALL_SHAPES(I5, invariantI5<R, C>(F, fb.a, o))
ARIES_FD_INVARIANT_ALL_SHAPES(I7, invariantI7<R, C>(F, fb.a, fb.b, o))

// Smith et al. 2019 invariants (I1 = f: its gradient is the rotation R, its Hessian dR/dF).
ARIES_FD_INVARIANT_ALL_SHAPES(I1, invariantI1<R, C>(F, o))
ARIES_FD_INVARIANT_ALL_SHAPES(I2, invariantI2<R, C>(F, o))
ARIES_FD_INVARIANT(I3, 3, 3, invariantI3(F, o))
ARIES_FD_INVARIANT(I3, 2, 2, invariantI3(F, o))
ARIES_FD_INVARIANT(I3, 3, 2, invariantI3(F, o))

// The closed-form stretch invariants and the singularity measure.
ARIES_FD_INVARIANT_ALL_SHAPES(I4, invariantI4<R, C>(F, fb.a, o))
ARIES_FD_INVARIANT_ALL_SHAPES(I6, invariantI6<R, C>(F, fb.a, fb.b, o))
ARIES_FD_INVARIANT_ALL_SHAPES(alpha, alphaMeasure<R, C>(F, o))

// The FD checker itself must reject a wrong derivative (otherwise every test above could pass vacuously): perturb
// I4's PK1 or Hessian by a small relative amount and expect the best FD error to exceed the tolerance.
TEST(FdChecker, RejectsWrongDerivatives) {
  Rng rng(7);
  const Mat<3, 3> F = randomF<3, 3>(rng);
  const Vec<3> a = randomUnit<3>(rng);
  const auto good = [&](const Mat<3, 3> &G, Order o) { return invariantI4<3, 3>(G, a, o); };
  const auto rep = finiteDifferences<3, 3>(good, F);
  EXPECT_LT(rep.gradErr, kFdTol);
  EXPECT_LT(rep.hessErr, kFdTol);
  // Wrong PK1 by 1e-4 relative in one entry, only where the Hessian is requested (as an assembly bug would be).
  const auto badGrad = [&](const Mat<3, 3> &G, Order o) {
    auto d = invariantI4<3, 3>(G, a, o);
    if (o == Order::Hessian) d.grad[4] += 1e-4 * d.grad.norm();
    return d;
  };
  EXPECT_GT((finiteDifferences<3, 3>(badGrad, F).gradErr), 5e-5);
  // Hessian wrong by 1e-5 relative in one symmetric pair of entries.
  const auto badHess = [&](const Mat<3, 3> &G, Order o) {
    auto d = invariantI4<3, 3>(G, a, o);
    if (o == Order::Hessian) {
      d.hess(1, 5) += 1e-5 * d.hess.norm();
      d.hess(5, 1) += 1e-5 * d.hess.norm();
    }
    return d;
  };
  EXPECT_GT((finiteDifferences<3, 3>(badHess, F).hessErr), 5e-6);
  // A missing factor 2 in a gradient shows up as an O(1) error.
  const auto halfGrad = [&](const Mat<3, 3> &G, Order o) {
    auto d = invariantIC<3, 3>(G, o);
    if (o == Order::Hessian) d.grad *= 0.5;
    return d;
  };
  EXPECT_GT((finiteDifferences<3, 3>(halfGrad, F).gradErr), 0.4);
}

// Known closed-form values at simple F (a second, non-FD anchor for the invariant kernels).
TEST(InvariantValues, ClosedFormAtDiagonalF) {
  Mat<3, 3> F = Vec<3>(2.0, 3.0, 0.5).asDiagonal();
  F(0, 1) = 0.0;
  const Vec<3> a = Vec<3>(1.0, 2.0, 2.0) / 3.0, b = Vec<3>(0.0, 0.6, 0.8);
  EXPECT_DOUBLE_EQ((invariantIC<3, 3>(F).value), 4.0 + 9.0 + 0.25);
  EXPECT_DOUBLE_EQ((invariantIIC<3, 3>(F).value), 16.0 + 81.0 + 0.0625);
  EXPECT_DOUBLE_EQ(invariantJ(F).value, 3.0);
  // I5 = |F a|^2, I4 = a^T S a with S = F (symmetric PD, R = I), I6 = a^T S b, I7 = a^T C b.
  const Vec<3> Fa = F * a, Fb = F * b;
  EXPECT_NEAR((invariantI5<3, 3>(F, a).value), Fa.squaredNorm(), 1e-14);
  EXPECT_NEAR((invariantI7<3, 3>(F, a, b).value), Fa.dot(Fb), 1e-14);
  EXPECT_NEAR((invariantI4<3, 3>(F, a).value), a.dot(F * a), 1e-13);
  EXPECT_NEAR((invariantI6<3, 3>(F, a, b).value), a.dot(F * b), 1e-13);
  EXPECT_NEAR((invariantVC<3, 3>(F, fiberTensor<3>(a)).value), (F.transpose() * F * a).squaredNorm(), 1e-12);
  EXPECT_NEAR((invariantI8<3>(F, fiberTensor<3>(a)).value), 3.0, 1e-14);
  EXPECT_NEAR((invariantI1<3, 3>(F).value), 5.5, 1e-14);
  EXPECT_NEAR((alphaMeasure<3, 3>(F).value), 8.0 * 5.0 * 2.5 * 3.5, 1e-11);
  // Cloth: F = [[1,0],[0,2],[0,0]] -> sqrt(III_C) = 2, f = 3, alpha = f sqrt(III_C) = 6.
  Mat<3, 2> G = Mat<3, 2>::Zero();
  G(0, 0) = 1.0;
  G(1, 1) = 2.0;
  EXPECT_NEAR((invariantIIIC<3>(G).value), 4.0, 1e-14);
  EXPECT_NEAR(invariantI3(G).value, 2.0, 1e-14);
  EXPECT_NEAR((invariantI1<3, 2>(G).value), 3.0, 1e-14);
  EXPECT_NEAR((alphaMeasure<3, 2>(G).value), 6.0, 1e-13);
  EXPECT_NEAR((invariantVIC<3>(G, crossFiberTensor<2>(Vec<2>(1, 0), Vec<2>(0.6, 0.8))).value), 4.0 * 0.6, 1e-14);
}

}  // namespace
}  // namespace aries::test
