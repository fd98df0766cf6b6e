#pragma once
// Shortest decimal text that reads back to exactly the same double (std::to_chars; at most
// 17 significant digits, locale-independent), for the ASCII writers.
#include <charconv>
#include <ostream>
#include <string>
#include <string_view>

namespace cf {

inline void write_real(std::ostream& os, double v) {
    char buf[32];
    auto res = std::to_chars(buf, buf + sizeof buf, v);
    os.write(buf, res.ptr - buf);
}

// Text gathered in a buffer and handed to the stream in large pieces: a fragment's OBJ is a few
// million numbers, and one ostream insertion per number (a sentry, a locale lookup for integers)
// cost about as much as formatting them. Numbers are written as write_real and operator<< on the
// "C" locale write them (to_chars), so the bytes are the same.
class TextOut {
public:
    explicit TextOut(std::ostream& os) : os_(&os) { buf_.reserve(kFlushAt + 256); }
    // Text appended to `into` instead (a piece formatted on its own task, written later in order).
    explicit TextOut(std::string& into) : into_(&into) { buf_.reserve(kFlushAt + 256); }
    ~TextOut() { flush(); }
    TextOut(const TextOut&) = delete;
    TextOut& operator=(const TextOut&) = delete;

    TextOut& operator<<(char c) {
        buf_.push_back(c);
        return *this;
    }
    TextOut& operator<<(std::string_view s) {
        buf_.append(s);
        return may_flush();
    }
    TextOut& operator<<(double v) { return number(v); }
    TextOut& operator<<(int v) { return number(v); }
    TextOut& operator<<(long v) { return number(v); }
    TextOut& operator<<(unsigned long v) { return number(v); }
    void flush() {
        if (os_) os_->write(buf_.data(), std::streamsize(buf_.size()));
        else into_->append(buf_);
        buf_.clear();
    }
    // Text already formatted, passed on as it is after what came before.
    void write_formatted(std::string_view s) {
        flush();
        if (os_) os_->write(s.data(), std::streamsize(s.size()));
        else into_->append(s);
    }

private:
    static constexpr std::size_t kFlushAt = std::size_t(1) << 20;
    template <class T>
    TextOut& number(T v) {
        char tmp[32];
        const auto res = std::to_chars(tmp, tmp + sizeof tmp, v);
        buf_.append(tmp, std::size_t(res.ptr - tmp));
        return may_flush();
    }
    TextOut& may_flush() {
        if (buf_.size() >= kFlushAt) flush();
        return *this;
    }
    std::ostream* os_ = nullptr;
    std::string* into_ = nullptr;
    std::string buf_;
};

}  // namespace cf
