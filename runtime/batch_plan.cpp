#include "runtime/batch_plan.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace cf::runtime::batch {

namespace fs = std::filesystem;

std::string row_completion(const fs::path& row_dir, const Row& row, bool fast) {
    const fs::path report = row_dir / "report.json";
    std::error_code ec;
    if (!fs::is_regular_file(report, ec)) return "missing";
    YAML::Node r;
    try {
        r = YAML::LoadFile(report.string());  // JSON is YAML
    } catch (const YAML::Exception&) {
        return "unreadable";
    }
    if (!r.IsMap() || !r["status"]) return "unreadable";
    const std::string status = r["status"].as<std::string>();
    if (status != "ok") return status == "cancelled" ? "cancelled" : "failed";
    // The same row asked for now? A changed load or mesh must not be skipped as done.
    std::vector<std::string> overrides;
    if (r["overrides"] && r["overrides"].IsSequence())
        for (const auto& o : r["overrides"]) overrides.push_back(o.as<std::string>());
    const bool same = r["pipeline"] && r["pipeline"].as<std::string>() == row.pipeline && overrides == set_arguments(row) &&
                      r["fast"] && r["fast"].as<bool>() == fast;
    return same ? "ok" : "stale";
}

int rows_per_task(double row_seconds, double task_overhead_seconds, double max_overhead_fraction) {
    if (!(row_seconds > 0) || !(task_overhead_seconds > 0) || !(max_overhead_fraction > 0)) return 1;
    // overhead / (R row_seconds) <= fraction
    const double r = std::ceil(task_overhead_seconds / (max_overhead_fraction * row_seconds) - 1e-9);
    return static_cast<int>(std::clamp(r, 1.0, 10000.0));
}

std::vector<std::vector<std::size_t>> pack_rows(std::size_t rows, int rows_per_task) {
    const std::size_t r = static_cast<std::size_t>(std::max(1, rows_per_task));
    std::vector<std::vector<std::size_t>> tasks;
    for (std::size_t i = 0; i < rows; ++i) {
        if (i % r == 0) tasks.emplace_back();
        tasks.back().push_back(i);
    }
    return tasks;
}

std::vector<long> tasks_with_pending_rows(const std::vector<std::vector<std::size_t>>& tasks,
                                          const std::vector<bool>& row_complete) {
    std::vector<long> r;
    for (std::size_t t = 0; t < tasks.size(); ++t)
        for (std::size_t row : tasks[t])
            if (row >= row_complete.size() || !row_complete[row]) {
                r.push_back(static_cast<long>(t));
                break;
            }
    return r;
}

std::string index_ranges(const std::vector<long>& s) {
    std::ostringstream o;
    for (std::size_t i = 0; i < s.size();) {
        std::size_t j = i;
        while (j + 1 < s.size() && s[j + 1] == s[j] + 1) ++j;
        if (i) o << ',';
        o << s[i];
        if (j > i) o << '-' << s[j];
        i = j + 1;
    }
    return o.str();
}

std::vector<ArrayChunk> split_into_arrays(const std::vector<long>& tasks, long max_array_size, int max_parallel) {
    std::vector<ArrayChunk> chunks;
    const long m = std::max(1L, max_array_size);
    for (long t : tasks) {
        const long offset = (t / m) * m;
        if (chunks.empty() || chunks.back().offset != offset) chunks.push_back({offset, {}, ""});
        chunks.back().indices.push_back(t - offset);
    }
    for (auto& c : chunks) {
        c.array_spec = index_ranges(c.indices);
        if (max_parallel > 0) c.array_spec += "%" + std::to_string(max_parallel);
    }
    return chunks;
}

long parse_max_array_size(const std::string& config, long fallback) {
    std::istringstream in(config);
    std::string line;
    while (std::getline(in, line)) {
        const auto k = line.find("MaxArraySize");
        const auto eq = line.find('=');
        if (k == std::string::npos || eq == std::string::npos || eq < k) continue;
        try {
            const long v = std::stol(line.substr(eq + 1));
            return v > 0 ? v : fallback;
        } catch (const std::exception&) {
            return fallback;
        }
    }
    return fallback;
}

}  // namespace cf::runtime::batch
