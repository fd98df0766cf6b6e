// The crackflow executable's heap: jemalloc (linked only into the executable, see
// runtime/CMakeLists.txt), configured here at link time, before the first allocation.
//
// Why: a fracture run allocates and frees hundreds of megabytes in large pieces (the BEM blocks of
// every step, level-set leaves, fragment grids). glibc's malloc returned most of it to the kernel
// and took it back page by page: about 90,000 page faults per edge_crack_mode3 run, 8 % of its CPU
// time on this virtual machine, where a fault costs several microseconds. With jemalloc keeping
// freed pages for reuse and backing its memory with transparent huge pages (2 MiB, one fault
// instead of 512) whole runs of the thesis cases are 1.1-1.35x faster, every output byte for byte
// the same (docs/performance.md, "The heap").
//
// thp:always          madvise(MADV_HUGEPAGE) on jemalloc's memory (the kernel's THP mode is
//                     "madvise" on Debian's default)
// metadata_thp:always the same for its own bookkeeping
// dirty_decay_ms:-1   never hand freed pages back to the kernel while the process lives; a run's
// muzzy_decay_ms:-1   footprint is its peak either way, and a later step reuses them
//
// On a virtual machine whose host reclaims free guest memory, main turns the huge pages off for the
// process (runtime/huge_pages.hpp). MALLOC_CONF in the environment is read after this string and
// overrides it (e.g. to compare); with it set, main leaves the pages as MALLOC_CONF says.
extern "C" {
extern const char* malloc_conf;
const char* malloc_conf = "thp:always,metadata_thp:always,dirty_decay_ms:-1,muzzy_decay_ms:-1";
}
