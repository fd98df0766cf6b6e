// The rigid-body verification cases (docs/verification.md 23-28), as `crackflow verify` runs them.
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

using cf::testing::expect_verification_case_passes;

TEST(RigidVerification, BallisticFreeFall) { expect_verification_case_passes("ballistic_free_fall"); }
TEST(RigidVerification, BalancedTractions) { expect_verification_case_passes("balanced_tractions"); }
TEST(RigidVerification, HertzDuration) { expect_verification_case_passes("hertz_duration"); }

// Scene cases (docs/verification.md 26-28, nodes/scene_verification.cpp).
TEST(SceneVerification, FragmentMomentum) { expect_verification_case_passes("fragment_momentum"); }
TEST(SceneVerification, IncompleteCrackGrows) { expect_verification_case_passes("incomplete_crack_grows"); }
TEST(SceneVerification, SceneDeterminism) { expect_verification_case_passes("scene_determinism"); }
TEST(SceneVerification, BeamSelfWeight) { expect_verification_case_passes("beam_self_weight"); }
