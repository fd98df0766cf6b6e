// The propagation verification cases, as registered for `crackflow verify`.
#include "nodes/domain/verification_case.hpp"

#include <gtest/gtest.h>

namespace cf {
namespace {

const VerificationCase& find_case(const std::string& name) {
    for (const auto& c : verification_cases())
        if (c.name == name) return c;
    throw std::runtime_error("verification case " + name + " is not registered");
}

TEST(PropagateVerification, KinkAngle) {
    const VerificationResult r = find_case("kink_angle").run();
    EXPECT_TRUE(r.passed) << r.details;
    EXPECT_LE(r.error, r.tolerance) << r.details;
    std::cout << r.details << "\n";
}

TEST(PropagateVerification, PropagationSpeed) {
    const VerificationResult r = find_case("propagation_speed").run();
    EXPECT_TRUE(r.passed) << r.details;
    std::cout << r.details << "\n";
}

// Case 8: the whole fracture loop (pipeline) on the edge-cracked cube under mode I.
TEST(PropagateVerification, EdgeCrackModeOnePlanar) {
    const VerificationResult r = find_case("edge_crack_mode1_planar").run();
    EXPECT_TRUE(r.passed) << r.details;
    EXPECT_LE(r.error, r.tolerance) << r.details;
    std::cout << r.details << "\n";
}

}  // namespace
}  // namespace cf
