#include "graph/input_paths.hpp"

#include <cstdlib>
#include <system_error>

namespace cf::graph {

namespace {

// The directories of a ':'-separated environment variable (empty entries skipped), then `builtin`.
std::vector<std::filesystem::path> search_path(const char* variable, const char* builtin) {
    std::vector<std::filesystem::path> dirs;
    if (const char* env = std::getenv(variable)) {
        const std::string text = env;
        std::size_t start = 0;
        while (start <= text.size()) {
            const std::size_t end = std::min(text.find(':', start), text.size());
            if (end > start) dirs.emplace_back(text.substr(start, end - start));
            start = end + 1;
        }
    }
    if (builtin) dirs.emplace_back(builtin);
    return dirs;
}

InputFileSearch find_file(const std::string& value, const std::filesystem::path& base_dir,
                          const std::vector<std::filesystem::path>& search) {
    InputFileSearch r;
    const std::filesystem::path p(value);
    std::vector<std::filesystem::path> candidates;
    if (p.is_absolute()) {
        candidates.push_back(p);
    } else {
        candidates.push_back(base_dir / p);
        for (const auto& d : search) candidates.push_back(d / p);
    }
    for (const auto& c : candidates) {
        std::error_code ec;
        const std::string abs = std::filesystem::absolute(c, ec).lexically_normal().string();
        r.tried.push_back(abs);
        if (std::filesystem::exists(abs, ec) && !std::filesystem::is_directory(abs, ec)) {
            r.found = abs;
            break;
        }
    }
    return r;
}

}  // namespace

// The build's data and crackflow's own pipelines directories (graph/CMakeLists.txt); none when
// compiled without them.
#ifndef CRACKFLOW_DATA_DIR
#define CRACKFLOW_DATA_DIR nullptr
#endif
#ifndef CRACKFLOW_PIPELINE_DIR
#define CRACKFLOW_PIPELINE_DIR nullptr
#endif

std::vector<std::filesystem::path> data_search_path() { return search_path(kDataPathVariable, CRACKFLOW_DATA_DIR); }

std::vector<std::filesystem::path> pipeline_search_path() {
    return search_path(kPipelinePathVariable, CRACKFLOW_PIPELINE_DIR);
}

InputFileSearch find_input_file(const std::string& value, const std::filesystem::path& base_dir) {
    return find_file(value, base_dir, data_search_path());
}

InputFileSearch find_pipeline_file(const std::string& value, const std::filesystem::path& base_dir) {
    return find_file(value, base_dir, pipeline_search_path());
}

}  // namespace cf::graph
