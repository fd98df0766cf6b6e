#include "graph/json_writer.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace cf::graph {

void JsonWriter::before_value() {
    if (after_key_) {
        after_key_ = false;
        return;
    }
    if (!first_.empty()) {
        if (!first_.back()) out_ << ",";
        first_.back() = false;
    }
}

JsonWriter& JsonWriter::begin_object() { before_value(); out_ << "{"; first_.push_back(true); return *this; }
JsonWriter& JsonWriter::end_object() { first_.pop_back(); out_ << "}"; return *this; }
JsonWriter& JsonWriter::begin_array() { before_value(); out_ << "["; first_.push_back(true); return *this; }
JsonWriter& JsonWriter::end_array() { first_.pop_back(); out_ << "]"; return *this; }

JsonWriter& JsonWriter::key(const std::string& k) {
    before_value();
    out_ << escape(k) << ":";
    after_key_ = true;
    return *this;
}

JsonWriter& JsonWriter::value(const std::string& s) { before_value(); out_ << escape(s); return *this; }
JsonWriter& JsonWriter::value(double d) {
    before_value();
    if (!std::isfinite(d)) {
        out_ << "null";
    } else {
        // Shortest of 15 or 17 significant digits that reads back to the same double.
        char buf[32];
        std::snprintf(buf, sizeof buf, "%.15g", d);
        if (std::strtod(buf, nullptr) != d) std::snprintf(buf, sizeof buf, "%.17g", d);
        out_ << buf;
    }
    return *this;
}
JsonWriter& JsonWriter::value(long long i) { before_value(); out_ << i; return *this; }
JsonWriter& JsonWriter::value(bool b) { before_value(); out_ << (b ? "true" : "false"); return *this; }
JsonWriter& JsonWriter::null() { before_value(); out_ << "null"; return *this; }

// Strings are escaped for JSON and kept valid UTF-8: a byte that does not start a well-formed
// UTF-8 sequence (e.g. a Latin-1 file name in a parameter) becomes U+FFFD, so report.json always
// parses with a strict reader.
std::string JsonWriter::escape(const std::string& s) {
    std::string r = "\"";
    const std::size_t n = s.size();
    for (std::size_t i = 0; i < n;) {
        const unsigned char c = static_cast<unsigned char>(s[i]);
        if (c < 0x80) {
            switch (c) {
                case '"': r += "\\\""; break;
                case '\\': r += "\\\\"; break;
                case '\n': r += "\\n"; break;
                case '\r': r += "\\r"; break;
                case '\t': r += "\\t"; break;
                default:
                    if (c < 0x20) {
                        char buf[8];
                        std::snprintf(buf, sizeof buf, "\\u%04x", c);
                        r += buf;
                    } else {
                        r += static_cast<char>(c);
                    }
            }
            ++i;
            continue;
        }
        // Length and minimum code point of the sequence this lead byte announces (no overlongs,
        // no surrogates, nothing above U+10FFFF).
        std::size_t len = 0;
        unsigned int cp = 0, min = 0;
        if ((c & 0xE0) == 0xC0) len = 2, cp = c & 0x1F, min = 0x80;
        else if ((c & 0xF0) == 0xE0) len = 3, cp = c & 0x0F, min = 0x800;
        else if ((c & 0xF8) == 0xF0) len = 4, cp = c & 0x07, min = 0x10000;
        bool ok = len > 0 && i + len <= n;
        for (std::size_t k = 1; ok && k < len; ++k) {
            const unsigned char cc = static_cast<unsigned char>(s[i + k]);
            ok = (cc & 0xC0) == 0x80;
            cp = (cp << 6) | (cc & 0x3F);
        }
        ok = ok && cp >= min && cp <= 0x10FFFF && !(cp >= 0xD800 && cp <= 0xDFFF);
        if (ok) {
            r.append(s, i, len);
            i += len;
        } else {
            r += "\xEF\xBF\xBD";  // U+FFFD REPLACEMENT CHARACTER
            ++i;
        }
    }
    return r + "\"";
}

}  // namespace cf::graph
