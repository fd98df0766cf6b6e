// The initiation verification case, as registered for `crackflow verify`.
#include "nodes/domain/verification_case.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

TEST(InitiateVerification, SurfaceStressUniaxial) {
    for (const auto& c : verification_cases())
        if (c.name == "surface_stress_uniaxial") {
            const VerificationResult r = c.run();
            EXPECT_TRUE(r.passed) << r.details;
            EXPECT_LE(r.error, 0.01) << r.details;
            std::cout << r.details << "\n";
            return;
        }
    FAIL() << "surface_stress_uniaxial is not registered";
}

}  // namespace
}  // namespace cf
