// The rule that keeps a multigrid hierarchy across Newton systems (solver/preconditioner_reuse.hpp,
// -multigrid_reuse_growth): the first system builds; later ones keep it while the last solve took at most growth x the
// iterations of the hierarchy's first solve (10 at least), for at most three systems; a slower or failed solve makes
// the next system build, a solve with a kept one stops at the limit; off, every system builds.
#include "solver/preconditioner_reuse.hpp"

#include <gtest/gtest.h>

using aries::solver::PreconditionerReuse;

TEST(PreconditionerReuse, OffBuildsEverySystem) {
  PreconditionerReuse rule;
  rule.enable(0.0);
  for (int k = 0; k < 3; ++k) {
    EXPECT_TRUE(rule.beginSystem());
    rule.endSystem(20, true);
  }
}

TEST(PreconditionerReuse, KeepsWhileSolvesStayFast) {
  PreconditionerReuse rule;
  rule.enable(1.5);
  EXPECT_TRUE(rule.beginSystem());  // nothing kept yet
  EXPECT_TRUE(rule.built());
  rule.endSystem(23, true);
  EXPECT_FALSE(rule.beginSystem());  // the peer box's counts: 23, 27, 29 with one hierarchy
  EXPECT_FALSE(rule.built());
  rule.endSystem(27, true);
  EXPECT_FALSE(rule.beginSystem());
  rule.endSystem(29, true);
  EXPECT_TRUE(rule.rebuildNext());  // three systems served: the next builds
  EXPECT_TRUE(rule.beginSystem());
  rule.endSystem(30, true);  // the new hierarchy's first solve is the new reference
  EXPECT_FALSE(rule.beginSystem());
  rule.endSystem(45, true);  // 1.5 x 30: still kept
  EXPECT_FALSE(rule.rebuildNext());
}

// The rule (growth 1.5) after a hierarchy's first solve took `first` iterations and the second system, which keeps
// it, took `second`.
namespace {
PreconditionerReuse afterTwoSolves(long first, long second) {
  PreconditionerReuse rule;
  rule.enable(1.5);
  rule.beginSystem();
  rule.endSystem(first, true);
  EXPECT_FALSE(rule.beginSystem());
  rule.endSystem(second, true);
  return rule;
}
}  // namespace

TEST(PreconditionerReuse, SlowSolveBuildsAgain) {
  EXPECT_FALSE(afterTwoSolves(23, 34).rebuildNext());  // below 1.5 x 23 = 34.5: still kept
  EXPECT_TRUE(afterTwoSolves(23, 35).rebuildNext());   // above 1.5 x 23: the next system builds
}

TEST(PreconditionerReuse, FewIterationsAreJudgedAgainstTen) {
  EXPECT_FALSE(afterTwoSolves(3, 15).rebuildNext());  // 5x the first solve, but within 1.5 x 10
  EXPECT_TRUE(afterTwoSolves(3, 16).rebuildNext());
}

TEST(PreconditionerReuse, FailuresBuildAgain) {
  PreconditionerReuse rule;
  rule.enable(1.5);
  rule.beginSystem();
  rule.endSystem(20, true);
  EXPECT_FALSE(rule.beginSystem());
  rule.endSystem(5, false);  // a kept hierarchy failed (CG indefinite, say)
  EXPECT_TRUE(rule.rebuildNext());
  EXPECT_TRUE(rule.beginSystem());
  rule.endSystem(40, false);  // a new one failed too: no reference, the next system builds again
  EXPECT_TRUE(rule.beginSystem());
  rule.endSystem(12, true);
  EXPECT_FALSE(rule.beginSystem());
  EXPECT_TRUE(rule.beginSystem(true));  // forced (a filtered re-solve's new matrix)
  rule.endSystem(13, true);
  EXPECT_FALSE(rule.rebuildNext());
}

TEST(PreconditionerReuse, KeptHierarchyStopsAtItsLimit) {
  PreconditionerReuse rule;
  rule.enable(1.5);
  EXPECT_EQ(rule.iterationLimit(), -1);  // no system in progress
  rule.beginSystem();
  EXPECT_EQ(rule.iterationLimit(), -1);  // a new hierarchy solves to the end
  rule.endSystem(97, true);
  rule.beginSystem();
  EXPECT_EQ(rule.iterationLimit(), 145);  // 1.5 x 97
  rule.endSystem(145, false);             // stopped there: the next system builds
  EXPECT_EQ(rule.iterationLimit(), -1);
  EXPECT_TRUE(rule.beginSystem());
  EXPECT_EQ(rule.iterationLimit(), -1);
  rule.endSystem(4, true);
  rule.beginSystem();
  EXPECT_EQ(rule.iterationLimit(), 15);  // 1.5 x 10 at least
  PreconditionerReuse off;
  off.enable(0.0);
  off.beginSystem();
  EXPECT_EQ(off.iterationLimit(), -1);
}
