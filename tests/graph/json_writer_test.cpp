// report.json is always valid UTF-8 JSON: strings are escaped and bytes that are not UTF-8 become U+FFFD.
#include "graph/json_writer.hpp"

#include <gtest/gtest.h>

using cf::graph::JsonWriter;

TEST(JsonWriter, EscapesControlCharactersAndQuotes) {
    EXPECT_EQ(JsonWriter::escape("a\"b\\c\nd\x01"), "\"a\\\"b\\\\c\\nd\\u0001\"");
}

TEST(JsonWriter, KeepsValidUtf8AndReplacesInvalidBytes) {
    // Valid: e-acute (2 bytes), euro sign (3), U+1F600 (4).
    const std::string ok = "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80";
    EXPECT_EQ(JsonWriter::escape(ok), "\"" + ok + "\"");
    const std::string fffd = "\xEF\xBF\xBD";
    // A Latin-1 byte, a lone continuation byte, a truncated sequence, an overlong '/', a surrogate.
    EXPECT_EQ(JsonWriter::escape("caf\xE9"), "\"caf" + fffd + "\"");
    EXPECT_EQ(JsonWriter::escape("\x80x"), "\"" + fffd + "x\"");
    EXPECT_EQ(JsonWriter::escape("\xE2\x82"), "\"" + fffd + fffd + "\"");
    EXPECT_EQ(JsonWriter::escape("\xC0\xAF"), "\"" + fffd + fffd + "\"");
    EXPECT_EQ(JsonWriter::escape("\xED\xA0\x80"), "\"" + fffd + fffd + fffd + "\"");
}
