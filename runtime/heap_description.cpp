#include "runtime/heap_description.hpp"

#include "runtime/huge_pages.hpp"

#include <dlfcn.h>
#include <gnu/libc-version.h>
#include <sys/types.h>

#include <cstddef>

namespace cf::runtime {

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)

std::string heap_description() { return "the sanitizer's allocator"; }

#else

namespace {

// jemalloc's mallctl, if jemalloc is this process's malloc (not linked here: the library and
// tests run on whatever malloc their executable has).
using Mallctl = int (*)(const char*, void*, std::size_t*, void*, std::size_t);

std::string read_string(Mallctl ctl, const char* name) {
    const char* v = nullptr;
    std::size_t len = sizeof v;
    return ctl(name, &v, &len, nullptr, 0) == 0 && v ? std::string(v) : std::string("?");
}

std::string read_ssize(Mallctl ctl, const char* name) {
    ssize_t v = 0;
    std::size_t len = sizeof v;
    return ctl(name, &v, &len, nullptr, 0) == 0 ? std::to_string(v) : std::string("?");
}

}  // namespace

std::string heap_description() {
    auto ctl = reinterpret_cast<Mallctl>(dlsym(RTLD_DEFAULT, "mallctl"));
    if (!ctl) return std::string("glibc ") + gnu_get_libc_version() + " malloc";
    const std::string pages = huge_pages_note();
    return "jemalloc " + read_string(ctl, "version") + " (thp: " + read_string(ctl, "opt.thp") +
           ", dirty_decay_ms: " + read_ssize(ctl, "opt.dirty_decay_ms") + ")" + (pages.empty() ? "" : "; " + pages);
}

#endif

}  // namespace cf::runtime
