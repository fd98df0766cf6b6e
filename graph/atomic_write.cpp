#include "graph/atomic_write.hpp"

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <mutex>
#include <set>
#include <stdexcept>
#include <streambuf>
#include <system_error>
#include <thread>
#include <unistd.h>
#include <vector>

namespace cf::graph {

namespace {

// A file stream buffer that keeps the first OS error of any write and of the close, so the
// message can name it ("File too large", "No space left on device") instead of guessing; an
// std::ofstream only says that something failed, and its close is not checked at all.
class CheckedFileBuffer : public std::streambuf {
public:
    explicit CheckedFileBuffer(const std::filesystem::path& path) : buffer_(1 << 16) {
        fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
        if (fd_ < 0) error_ = errno;
        setp(buffer_.data(), buffer_.data() + buffer_.size());
    }
    ~CheckedFileBuffer() override {
        if (fd_ >= 0) ::close(fd_);
    }
    bool is_open() const { return fd_ >= 0; }
    int error() const { return error_; }
    // Writes what is buffered and closes; false (with error() set) if any write or the close failed.
    bool close() {
        drain();
        if (fd_ >= 0 && ::close(fd_) != 0 && error_ == 0) error_ = errno;
        fd_ = -1;
        return error_ == 0;
    }

protected:
    int_type overflow(int_type ch) override {
        if (!drain()) return traits_type::eof();
        if (!traits_type::eq_int_type(ch, traits_type::eof())) {
            *pptr() = traits_type::to_char_type(ch);
            pbump(1);
        }
        return traits_type::not_eof(ch);
    }
    int sync() override { return drain() ? 0 : -1; }
    // Seekable like a file (OpenVDB's archive writer goes back to fill in grid offsets).
    pos_type seekoff(off_type off, std::ios_base::seekdir dir, std::ios_base::openmode) override {
        if (!drain()) return pos_type(off_type(-1));
        const int whence = dir == std::ios_base::beg ? SEEK_SET : dir == std::ios_base::cur ? SEEK_CUR : SEEK_END;
        const off_t at = ::lseek(fd_, static_cast<off_t>(off), whence);
        if (at < 0) return pos_type(off_type(-1));
        return pos_type(off_type(at));
    }
    pos_type seekpos(pos_type pos, std::ios_base::openmode which) override {
        return seekoff(off_type(pos), std::ios_base::beg, which);
    }

private:
    bool drain() {
        const char* p = pbase();
        std::size_t left = static_cast<std::size_t>(pptr() - pbase());
        while (left > 0 && error_ == 0 && fd_ >= 0) {
            const ssize_t n = ::write(fd_, p, left);
            if (n < 0) {
                if (errno == EINTR) continue;
                error_ = errno;
            } else {
                p += n;
                left -= static_cast<std::size_t>(n);
            }
        }
        setp(buffer_.data(), buffer_.data() + buffer_.size());
        return error_ == 0;
    }
    std::vector<char> buffer_;
    int fd_ = -1;
    int error_ = 0;
};

}  // namespace

namespace {

// The temporaries being written now, and whether the run was abandoned (and by which thread).
struct PendingWrites {
    std::mutex mutex;
    std::set<std::filesystem::path> temporaries;
    bool abandoned = false;
    std::thread::id survivor;
    bool may_write() const { return !abandoned || std::this_thread::get_id() == survivor; }
};

PendingWrites& pending() {
    static PendingWrites p;
    return p;
}

std::runtime_error abandoned_error(const std::filesystem::path& path) {
    return std::runtime_error("not writing " + path.string() + ": the run was cancelled");
}

}  // namespace

int abandon_pending_writes() {
    PendingWrites& p = pending();
    std::lock_guard<std::mutex> lock(p.mutex);
    p.abandoned = true;
    p.survivor = std::this_thread::get_id();
    int removed = 0;
    std::error_code ec;
    for (const auto& tmp : p.temporaries) removed += std::filesystem::remove(tmp, ec) ? 1 : 0;
    p.temporaries.clear();
    return removed;
}

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
    PendingWrites& p = pending();
    {
        std::lock_guard<std::mutex> lock(p.mutex);
        if (!p.may_write()) throw abandoned_error(path);
        p.temporaries.insert(tmp);
    }
    try {
        write(tmp);
    } catch (...) {
        std::lock_guard<std::mutex> lock(p.mutex);
        p.temporaries.erase(tmp);
        std::filesystem::remove(tmp, ec);
        throw;
    }
    // Renamed under the lock, so an abandoning thread sees either the temporary or the final file.
    std::lock_guard<std::mutex> lock(p.mutex);
    p.temporaries.erase(tmp);
    if (!p.may_write()) {
        std::filesystem::remove(tmp, ec);
        throw abandoned_error(path);
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
        CheckedFileBuffer buffer(tmp);
        if (!buffer.is_open())
            throw std::runtime_error("cannot open " + path.string() + " for writing: " + std::strerror(buffer.error()) +
                                     " (check the directory exists and is writable)");
        std::ostream f(&buffer);
        write(f);
        f.flush();
        if (!buffer.close() || !f)
            throw std::runtime_error("error while writing " + path.string() + ": " +
                                     (buffer.error() ? std::strerror(buffer.error()) : "the writer's stream failed") +
                                     " (is the disk full or a file-size limit set?); nothing was written under that name");
    });
}

}  // namespace cf::graph
