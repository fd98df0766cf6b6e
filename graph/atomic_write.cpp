#include "graph/atomic_write.hpp"

#include <atomic>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace cf::graph {

static std::filesystem::path temp_name(const std::filesystem::path& path) {
    static std::atomic<unsigned> counter{0};
    return path.parent_path() / ("." + path.filename().string() + ".tmp" + std::to_string(::getpid()) + "_" +
                                 std::to_string(counter++));
}

void write_atomically_via_path(const std::filesystem::path& path,
                               const std::function<void(const std::filesystem::path&)>& write) {
    std::error_code ec;
    if (path.has_parent_path()) {
        std::filesystem::create_directories(path.parent_path(), ec);
        if (ec) throw std::runtime_error("cannot create directory " + path.parent_path().string() + ": " + ec.message());
    }
    // Only a regular file (or nothing) may be replaced: the rename would swap a symlink for a file,
    // feed a FIFO or device nothing, and fails on a directory with a confusing message.
    const std::filesystem::file_status st = std::filesystem::symlink_status(path, ec);
    if (!ec && std::filesystem::exists(st) && !std::filesystem::is_regular_file(st)) {
        const char* what = std::filesystem::is_directory(st) ? "a directory"
                           : std::filesystem::is_symlink(st) ? "a symbolic link"
                                                             : "not a regular file (a FIFO, socket or device)";
        throw std::runtime_error("cannot write " + path.string() + ": it exists and is " + what +
                                 "; choose another output name or remove it");
    }
    auto tmp = temp_name(path);
    try {
        write(tmp);
    } catch (...) {
        std::filesystem::remove(tmp, ec);
        throw;
    }
    std::filesystem::rename(tmp, path, ec);
    if (ec) {
        const std::string why = ec.message();  // before remove() overwrites ec
        std::filesystem::remove(tmp, ec);
        throw std::runtime_error("cannot write " + path.string() + ": rename failed: " + why);
    }
}

void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
    write_atomically_via_path(path, [&](const std::filesystem::path& tmp) {
        std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
        if (!f) throw std::runtime_error("cannot open " + path.string() + " for writing (check the directory exists and is writable)");
        write(f);
        f.flush();
        if (!f) throw std::runtime_error("error while writing " + path.string() + " (disk full?)");
    });
}

}  // namespace cf::graph
