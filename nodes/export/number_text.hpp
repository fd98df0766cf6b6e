#pragma once
// Shortest decimal text that reads back to exactly the same double (std::to_chars; at most
// 17 significant digits, locale-independent), for the ASCII writers.
#include <charconv>
#include <ostream>

namespace cf {

inline void write_real(std::ostream& os, double v) {
    char buf[32];
    auto res = std::to_chars(buf, buf + sizeof buf, v);
    os.write(buf, res.ptr - buf);
}

}  // namespace cf
