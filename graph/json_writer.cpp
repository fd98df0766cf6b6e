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

std::string JsonWriter::escape(const std::string& s) {
    std::string r = "\"";
    for (unsigned char c : s) {
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
    }
    return r + "\"";
}

}  // namespace cf::graph
