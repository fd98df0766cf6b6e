#pragma once
// A verification case: a closed-form (or otherwise independent) check of the physics, run by
// `crackflow verify` and by ctest. Each stage contributes its cases (nodes/registration.hpp).
#include <functional>
#include <string>
#include <vector>

namespace cf {

struct VerificationResult {
    double error = 0;      // measured error (relative unless the details say otherwise)
    double tolerance = 0;  // the bar
    bool passed = false;   // usually error <= tolerance, but a case may require more (e.g. counts)
    std::string details;   // one line: what was measured, on which mesh
};

struct VerificationCase {
    std::string name;         // e.g. cube_tension_neumann
    std::string description;  // one line, with the verification.md case number
    std::function<VerificationResult()> run;
};

// All cases of all stages, sorted by name (nodes/register_all.cpp).
const std::vector<VerificationCase>& verification_cases();

}  // namespace cf
