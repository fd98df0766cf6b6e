#pragma once
// report.json: what ran, with which parameters and versions, how long each node took, how
// much memory the process peaked at, and the counts each node reported.
#include "graph/executor.hpp"

#include <string>
#include <vector>

namespace cf::runtime {

struct ReportContext {
    std::string pipeline_file;
    std::vector<std::string> overrides;  // --set texts
    bool fast = false;
    int threads = 0;
    std::vector<std::string> notes;  // run_notes(), computed once by the caller (summary.notes)
};

std::string report_json(const graph::Plan& plan, const graph::ExecutionResult& result, const ReportContext& ctx);

}  // namespace cf::runtime
