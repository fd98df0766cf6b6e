#include "graph/input_paths.hpp"

#include <cstdlib>
#include <system_error>

namespace cf::graph {

std::vector<std::filesystem::path> data_search_path() {
    std::vector<std::filesystem::path> dirs;
    if (const char* env = std::getenv(kDataPathVariable)) {
        const std::string text = env;
        std::size_t start = 0;
        while (start <= text.size()) {
            const std::size_t end = std::min(text.find(':', start), text.size());
            if (end > start) dirs.emplace_back(text.substr(start, end - start));  // empty entries are skipped
            start = end + 1;
        }
    }
#ifdef CRACKFLOW_DATA_DIR
    dirs.emplace_back(CRACKFLOW_DATA_DIR);
#endif
    return dirs;
}

InputFileSearch find_input_file(const std::string& value, const std::filesystem::path& base_dir) {
    InputFileSearch r;
    const std::filesystem::path p(value);
    std::vector<std::filesystem::path> candidates;
    if (p.is_absolute()) {
        candidates.push_back(p);
    } else {
        candidates.push_back(base_dir / p);
        for (const auto& d : data_search_path()) candidates.push_back(d / p);
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

}  // namespace cf::graph
