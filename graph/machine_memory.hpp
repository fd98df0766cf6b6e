#pragma once
// The machine's physical memory, against which user-sized allocations are checked before they are
// made (a dense BEM block, a remesh, a pipeline file): a request beyond it can only swap or be
// killed, so it is refused with the parameter to change instead.
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>

namespace cf {

// Bytes of physical memory (0 if the system does not say).
inline double physical_memory_bytes() {
    const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
    return pages > 0 && page > 0 ? double(pages) * double(page) : 0.0;
}

// What this process may allocate: the physical memory, or less under an address-space or data
// limit (ulimit -v / -d, a batch scheduler's cap).
inline double available_memory_bytes() {
    double m = physical_memory_bytes();
    for (int which : {RLIMIT_AS, RLIMIT_DATA}) {
        rlimit r{};
        if (::getrlimit(which, &r) == 0 && r.rlim_cur != RLIM_INFINITY) m = m > 0 ? std::min(m, double(r.rlim_cur)) : double(r.rlim_cur);
    }
    return m;
}

// Default budget for one node's dense matrices: half the physical memory (the rest for the
// operating system, the level sets and the blocks of the previous step held during an append).
inline double default_memory_budget_bytes() {
    const double m = available_memory_bytes();
    return m > 0 ? 0.5 * m : 4e9;
}

}  // namespace cf
