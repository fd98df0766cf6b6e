// The estimator verification cases (docs/verification.md 18-22), as `crackflow verify` runs them.
#include "nodes/domain/verification_case.hpp"

#include <gtest/gtest.h>

#include <iostream>

namespace {

void run_case(const std::string& name) {
    for (const auto& c : cf::verification_cases())
        if (c.name == name) {
            const cf::VerificationResult r = c.run();
            EXPECT_TRUE(r.passed) << r.details;
            EXPECT_LE(r.error, r.tolerance) << r.details;
            std::cout << r.details << "\n";
            return;
        }
    FAIL() << "verification case " << name << " is not registered";
}

}  // namespace

TEST(EstimateVerification, EstimatorEdgeCrackHalfspace) { run_case("estimator_edge_crack_halfspace"); }
TEST(EstimateVerification, EstimatorVsFullBem) { run_case("estimator_vs_full_bem"); }
TEST(EstimateVerification, EstimatorNoOscillation) { run_case("estimator_no_oscillation"); }
TEST(EstimateVerification, HybridSwitchContinuity) { run_case("hybrid_switch_continuity"); }
TEST(EstimateVerification, CodRhsUpdate) { run_case("cod_rhs_update"); }
