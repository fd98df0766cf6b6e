#pragma once
// Line-by-line reading of text mesh formats (OBJ, OFF, ASCII PLY, ASCII STL) with 1-based line
// numbers, whitespace tokenising and locale-independent number parsing (std::from_chars, so
// "0.1" reads back bit-exactly whatever the C locale says).
#include <string_view>
#include <vector>

namespace cf {

class TextScanner {
public:
    explicit TextScanner(std::string_view text, std::size_t start = 0) : text_(text), pos_(start) {}

    // Next line without its end-of-line characters (\n, \r\n or \r); false at end of text.
    bool next_line(std::string_view& line);
    long long line_number() const { return line_; }
    std::size_t position() const { return pos_; }  // byte offset just after the last line read

private:
    std::string_view text_;
    std::size_t pos_ = 0;
    long long line_ = 0;
};

// Splits on spaces and tabs (and any other ASCII control character).
void split_tokens(std::string_view line, std::vector<std::string_view>& tokens);
// A line with everything from the first `comment` character removed.
std::string_view strip_comment(std::string_view line, char comment);

// Whole-token parses; false if the token is not entirely a number. An optional leading '+' is
// accepted. parse_real accepts "nan"/"inf" so the caller can report them as such.
bool parse_real(std::string_view token, double& out);
bool parse_integer(std::string_view token, long long& out);

}  // namespace cf
