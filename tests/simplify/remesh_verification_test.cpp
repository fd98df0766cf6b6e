// The registered verification case rigid_translation_remeshed, as `crackflow verify` runs it: the
// bunny and the armadillo of libcgal-demo (installed by the README's test command), remeshed to
// 1000 triangles, a cap translated rigidly (traction below 1e-6 E |d| / L) and a uniform strain
// (no less accurate with K's rigid-motion rows than without).
#include "nodes/domain/verification_case.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <iostream>
#include <stdexcept>

namespace cf {
namespace {

TEST(RemeshVerification, RigidTranslationRemeshed) {
    setenv("CRACKFLOW_MESH_DATA", CF_REMESH_DATA_DIR, 0);  // the meshes this directory's CMakeLists extracted
    for (const auto& c : verification_cases())
        if (c.name == "rigid_translation_remeshed") {
            const VerificationResult r = c.run();
            std::cout << r.details << "\n";
            EXPECT_TRUE(r.passed) << r.details;
            EXPECT_LE(r.error, r.tolerance) << r.details;
            return;
        }
    FAIL() << "verification case rigid_translation_remeshed is not registered";
}

}  // namespace
}  // namespace cf
