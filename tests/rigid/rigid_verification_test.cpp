// The rigid-body verification cases (docs/verification.md 23-25), as `crackflow verify` runs them.
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

TEST(RigidVerification, BallisticFreeFall) { run_case("ballistic_free_fall"); }
TEST(RigidVerification, BalancedTractions) { run_case("balanced_tractions"); }
TEST(RigidVerification, HertzDuration) { run_case("hertz_duration"); }
