// The estimator verification cases (docs/verification.md 18-22), as `crackflow verify` runs them.
#include "tests/harness/node_harness.hpp"

#include <gtest/gtest.h>

using cf::testing::expect_verification_case_passes;

TEST(EstimateVerification, EstimatorEdgeCrackHalfspace) { expect_verification_case_passes("estimator_edge_crack_halfspace"); }
TEST(EstimateVerification, EstimatorVsFullBem) { expect_verification_case_passes("estimator_vs_full_bem"); }
TEST(EstimateVerification, EstimatorNoOscillation) { expect_verification_case_passes("estimator_no_oscillation"); }
TEST(EstimateVerification, HybridSwitchContinuity) { expect_verification_case_passes("hybrid_switch_continuity"); }
TEST(EstimateVerification, CodRhsUpdate) { expect_verification_case_passes("cod_rhs_update"); }
