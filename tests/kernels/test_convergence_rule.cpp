// The convergence rule of projected Newton (solver/convergence_rule.hpp): which directions certify a step, and how
// the certificate is reported. In particular the round-off path: a direction whose predicted decrease is below the
// energy's round-off certifies only a short step, at any iteration it reads energy_roundoff (never
// converged_initial), and a flat but long direction certifies nothing.
#include "solver/convergence_rule.hpp"

#include <gtest/gtest.h>

using aries::solver::classifyDirection;
using aries::solver::Convergence;
using aries::solver::DirectionMeasures;
using aries::solver::kRoundoffStepFactor;

namespace {

DirectionMeasures direction(int iteration, double stepInf, double slope) {
  DirectionMeasures m;
  m.linearConverged = true;
  m.iteration = iteration;
  m.stepInf = stepInf;
  m.stepTol = 1e-4;
  m.slope = slope;
  m.roundoff = 1e-9;
  return m;
}

}  // namespace

TEST(ConvergenceRule, SmallStepIsInitialAtIterationZeroElseNewtonStep) {
  EXPECT_EQ(classifyDirection(direction(0, 5e-5, 1.0)), Convergence::Initial);
  EXPECT_EQ(classifyDirection(direction(3, 5e-5, 1.0)), Convergence::NewtonStep);
  EXPECT_EQ(classifyDirection(direction(3, 1e-4, 1.0)), Convergence::NewtonStep);  // at the tolerance
}

TEST(ConvergenceRule, LongSteepDirectionIsNotConverged) {
  EXPECT_EQ(classifyDirection(direction(0, 1e-2, 1.0)), Convergence::None);
  EXPECT_EQ(classifyDirection(direction(7, 1e-2, 1.0)), Convergence::None);
}

TEST(ConvergenceRule, FlatShortDirectionIsRoundoffAtEveryIteration) {
  // Predicted decrease below round-off, step above the tolerance but within the factor: energy_roundoff, also at
  // iteration 0 (it used to read converged_initial there, and its step was applied).
  const double step = 0.5 * kRoundoffStepFactor * 1e-4;
  EXPECT_EQ(classifyDirection(direction(0, step, 1e-10)), Convergence::EnergyRoundoff);
  EXPECT_EQ(classifyDirection(direction(4, step, -1e-10)), Convergence::EnergyRoundoff);
}

TEST(ConvergenceRule, FlatButLongDirectionIsNotConverged) {
  // Iteration 0 flat but long: no certificate (it used to be accepted whatever its length).
  EXPECT_EQ(classifyDirection(direction(0, 2.0 * kRoundoffStepFactor * 1e-4, 1e-12)), Convergence::None);
  EXPECT_EQ(classifyDirection(direction(0, 1e3, 0.0)), Convergence::None);
  EXPECT_EQ(classifyDirection(direction(5, 1e3, 0.0)), Convergence::None);
}

TEST(ConvergenceRule, UnconvergedLinearSolveCertifiesNothing) {
  DirectionMeasures m = direction(0, 1e-8, 0.0);
  m.linearConverged = false;
  EXPECT_EQ(classifyDirection(m), Convergence::None);
}
