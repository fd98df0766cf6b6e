#include "nodes/import/text_scanner.hpp"

#include <charconv>

namespace cf {

bool TextScanner::next_line(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    std::size_t end = pos_;
    while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
    line = text_.substr(pos_, end - pos_);
    if (end < text_.size()) {
        if (text_[end] == '\r' && end + 1 < text_.size() && text_[end + 1] == '\n') ++end;
        ++end;
    }
    pos_ = end;
    ++line_;
    return true;
}

static bool is_space(char c) { return static_cast<unsigned char>(c) <= ' '; }

void split_tokens(std::string_view line, std::vector<std::string_view>& tokens) {
    tokens.clear();
    std::size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && is_space(line[i])) ++i;
        std::size_t start = i;
        while (i < line.size() && !is_space(line[i])) ++i;
        if (i > start) tokens.push_back(line.substr(start, i - start));
    }
}

std::string_view strip_comment(std::string_view line, char comment) {
    auto p = line.find(comment);
    return p == std::string_view::npos ? line : line.substr(0, p);
}

bool parse_real(std::string_view token, double& out) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), out);
    // Out-of-range values (1e999) come back as result_out_of_range; report them as non-numbers.
    return ec == std::errc() && ptr == token.data() + token.size();
}

bool parse_integer(std::string_view token, long long& out) {
    if (!token.empty() && token.front() == '+') token.remove_prefix(1);
    if (token.empty()) return false;
    auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), out);
    return ec == std::errc() && ptr == token.data() + token.size();
}

}  // namespace cf
