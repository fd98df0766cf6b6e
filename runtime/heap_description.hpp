#pragma once

#include <string>

namespace cf::runtime {

// The allocator this process runs on, as report.json's versions.allocator: jemalloc's version and
// the options that decide its speed here (thp, dirty_decay_ms, and whether huge pages were turned
// off for the process: runtime/huge_pages.hpp), or glibc's malloc. Looked up at
// run time (dlsym), so it tells what is in effect, also under LD_PRELOAD.
std::string heap_description();

}  // namespace cf::runtime
