#pragma once
// One check for "this call fails with an error whose message says ...", instead of hand-written
// try { ...; FAIL(); } catch (const E& e) { EXPECT_NE(std::string(e.what()).find(...), npos); }.
//   EXPECT_TRUE(cf::testing::throws<std::invalid_argument>([&] { make_box(spec); }, {"'size'", "axis y"}));
// Fails (printing the message) when nothing is thrown, when the exception is not an E, or when the
// message lacks one of the parts.
#include <gtest/gtest.h>

#include <exception>
#include <string>
#include <vector>

namespace cf::testing {

template <class E = std::exception, class F>
::testing::AssertionResult throws(F&& call, const std::vector<std::string>& parts = {}) {
    try {
        call();
    } catch (const E& e) {
        const std::string message = e.what();
        for (const std::string& p : parts)
            if (message.find(p) == std::string::npos)
                return ::testing::AssertionFailure() << "the message lacks \"" << p << "\": " << message;
        return ::testing::AssertionSuccess() << message;
    } catch (...) {
        std::string what = "(not a std::exception)";
        try {
            throw;
        } catch (const std::exception& e) {
            what = e.what();
        } catch (...) {
        }
        return ::testing::AssertionFailure() << "threw an exception of another type: " << what;
    }
    return ::testing::AssertionFailure() << "threw nothing";
}

}  // namespace cf::testing
