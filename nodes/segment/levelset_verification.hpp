#pragma once
// Verification cases 9-12 of docs/verification.md (geometry and topology), each runnable alone.
#include "nodes/domain/verification_case.hpp"

namespace cf {

VerificationResult verify_planar_cut_two_fragments();    // case 9
VerificationResult verify_interior_crack_one_fragment(); // case 10
VerificationResult verify_spindle_removed();             // case 11
VerificationResult verify_remesh_closed_manifold();      // case 12

}  // namespace cf
