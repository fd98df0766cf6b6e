#include "runtime/verify_command.hpp"

#include "graph/diagnostics.hpp"
#include "graph/json_writer.hpp"
#include "nodes/domain/verification_case.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>

namespace cf::runtime {

int verify_command(const std::vector<std::string>& case_names, bool json) {
    const auto& all = verification_cases();
    std::vector<const VerificationCase*> chosen;
    std::vector<std::string> names;
    for (const auto& c : all) names.push_back(c.name);
    for (const auto& n : case_names) {
        const VerificationCase* found = nullptr;
        for (const auto& c : all) if (c.name == n) found = &c;
        if (!found) {
            std::fprintf(stderr, "crackflow verify: error: unknown case '%s'\n  hint: %s\n", n.c_str(),
                         graph::did_you_mean(n, names).c_str());
            return 2;
        }
        chosen.push_back(found);
    }
    if (case_names.empty())
        for (const auto& c : all) chosen.push_back(&c);

    struct Row { const VerificationCase* c; VerificationResult r; double seconds; };
    std::vector<Row> rows;
    bool all_passed = true;
    for (const auto* c : chosen) {
        std::fprintf(stderr, "running %s ...\n", c->name.c_str());
        auto t0 = std::chrono::steady_clock::now();
        VerificationResult r;
        try {
            r = c->run();
        } catch (const std::exception& e) {
            r.passed = false;
            r.error = -1;
            r.details = std::string("exception: ") + e.what();
        }
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        all_passed = all_passed && r.passed;
        rows.push_back({c, r, s});
    }
    if (json) {
        graph::JsonWriter w;
        w.begin_object().key("cases").begin_array();
        for (const auto& row : rows)
            w.begin_object().key("name").value(row.c->name).key("error").value(row.r.error).key("tolerance")
                .value(row.r.tolerance).key("passed").value(row.r.passed).key("details").value(row.r.details)
                .key("seconds").value(row.seconds).end_object();
        w.end_array().end_object();
        std::printf("%s\n", w.str().c_str());
    } else {
        std::printf("%-30s %12s %12s %6s %8s  %s\n", "case", "error", "tolerance", "pass", "time[s]", "details");
        for (const auto& row : rows)
            std::printf("%-30s %12.3e %12.3e %6s %8.2f  %s\n", row.c->name.c_str(), row.r.error, row.r.tolerance,
                        row.r.passed ? "yes" : "NO", row.seconds, row.r.details.c_str());
        std::printf("%zu cases, %zu failed\n", rows.size(),
                    static_cast<std::size_t>(std::count_if(rows.begin(), rows.end(), [](const Row& r) { return !r.r.passed; })));
    }
    return all_passed ? 0 : 1;
}

}  // namespace cf::runtime
