#include "sceneio/text_check.h"

#include <gtest/gtest.h>

#include <string>

namespace raycast {
namespace {

using namespace std::string_literals;  // "...\0..."s keeps its NUL bytes

std::string first_bad(const std::string& text) {
    const std::optional<size_t> offset = find_non_text_byte(text);
    if (!offset) return "text";
    const Diagnostic d = non_text_diagnostic(text, *offset, "f.txt");
    EXPECT_EQ(d.severity, Severity::Error);
    EXPECT_EQ(d.source_line, "");  // the line holds a byte a terminal cannot show
    return std::to_string(*offset) + " " + format_diagnostic(d);
}

TEST(TextCheck, TextInAnyAsciiCompatibleEncodingPasses) {
    EXPECT_EQ(first_bad(""), "text");
    EXPECT_EQ(first_bad("v 1 2 3\r\n\tf 1 2 3\n\n   \n# note"), "text");
    // VT and FF are blanks; a control byte or a Latin-1 byte after a line's first character is left alone.
    EXPECT_EQ(first_bad("\v\fv 1\n# caf\xe9\nv 1 \x01 2\n"), "text");
    // Lines may start with UTF-8 of every length: é, 中, 😀, and a byte order mark.
    EXPECT_EQ(first_bad("\xc3\xa9\n\xe4\xb8\xad\n\xf0\x9f\x98\x80\n\xef\xbb\xbfv 1 2 3\n"), "text");
}

TEST(TextCheck, ANulAnywhereIsNotText) {
    EXPECT_EQ(first_bad("v 1 2 3\nv 1\0 2 3\n"s),
              "11 f.txt:2:4: error: this is not a text file: byte 0x00 (NUL) never appears in text\n");
    EXPECT_EQ(first_bad("\0"s), "0 f.txt:1:1: error: this is not a text file: byte 0x00 (NUL) never appears in text\n");
    // A zip archive's first bytes: "PK", 3, 4, then 20, 0.
    EXPECT_EQ(first_bad("PK\x03\x04\x14\0\0\0"s),
              "5 f.txt:1:6: error: this is not a text file: byte 0x00 (NUL) never appears in text\n");
}

TEST(TextCheck, AControlByteStartingALineIsNotText) {
    EXPECT_EQ(first_bad("v 1 2 3\n\x1b[31m\n"),
              "8 f.txt:2:1: error: this is not a text file: byte 0x1b is a control character at the start of a line\n");
    // The first byte after the line's blanks is the one that counts.
    EXPECT_EQ(first_bad("v\n \t\x01x\n"),
              "4 f.txt:2:3: error: this is not a text file: byte 0x01 is a control character at the start of a line\n");
    EXPECT_EQ(first_bad("\x7f"), "0 f.txt:1:1: error: this is not a text file: byte 0x7f is a control character at "
                                 "the start of a line\n");
}

TEST(TextCheck, ABytePast0x7fStartingALineMustBeginAUtf8Character) {
    const std::string message = " f.txt:1:1: error: this is not a text file: byte 0x";
    const std::string rest = " at the start of a line does not begin a UTF-8 character\n";
    EXPECT_EQ(first_bad("\x80"), "0" + message + "80" + rest);              // a continuation byte
    EXPECT_EQ(first_bad("\xc0\x80"), "0" + message + "c0" + rest);          // an overlong NUL
    EXPECT_EQ(first_bad("\xe0\x80\x80"), "0" + message + "e0" + rest);      // overlong
    EXPECT_EQ(first_bad("\xed\xa0\x80"), "0" + message + "ed" + rest);      // a surrogate, U+D800
    EXPECT_EQ(first_bad("\xf4\x90\x80\x80"), "0" + message + "f4" + rest);  // past U+10FFFF
    EXPECT_EQ(first_bad("\xf5\x80\x80\x80"), "0" + message + "f5" + rest);
    EXPECT_EQ(first_bad("\xe4\xb8"), "0" + message + "e4" + rest);          // cut short by the end
    EXPECT_EQ(first_bad("\xc3" "a"), "0" + message + "c3" + rest);         // no continuation
    // 中 in GBK: D6 D0. D6 would begin a 2-byte UTF-8 character, but D0 cannot continue one.
    EXPECT_EQ(first_bad("\xd6\xd0"), "0" + message + "d6" + rest);
    // A UTF-16 file (Notepad's "Unicode") starts with its byte order mark, FF FE (little-endian) or
    // FE FF, before any NUL: the message says what the file is and what to do.
    const std::string utf16 = ": the file is UTF-16 text (Notepad's \"Unicode\"); save it as UTF-8\n";
    EXPECT_EQ(first_bad("\xff\xfeP\0e\0"s), "0" + message + "ff" + rest.substr(0, rest.size() - 1) + utf16);
    EXPECT_EQ(first_bad("\xfe\xff\0P\0e"s), "0" + message + "fe" + rest.substr(0, rest.size() - 1) + utf16);
}

TEST(TextCheck, TheFirstBadByteInTheFileIsReported) {
    // A NUL before a bad line start, and a bad line start before a NUL.
    EXPECT_EQ(first_bad("a\0\n\x01\n"s).substr(0, 2), "1 ");
    EXPECT_EQ(first_bad("a\n\x01\n\0"s).substr(0, 2), "2 ");
}

// Old editors' line ends and end marks, turned into what the parsers read (as_unix_text).
std::string unix_text(const std::string& text) {
    std::string storage;
    return std::string(as_unix_text(text, storage));
}

TEST(TextCheck, ClassicMacLineBreaksBecomeLineFeeds) {
    EXPECT_EQ(unix_text("a 1\rb 2\r"), "a 1\nb 2\n");
    EXPECT_EQ(unix_text("\r\ra"), "\n\na");
    EXPECT_EQ(unix_text("a\r"), "a\n");
    // A file whose first line break is CR alone: a CRLF later keeps its CR, as a blank.
    EXPECT_EQ(unix_text("a\rb\r\nc"), "a\nb\r\nc");
    // The first line break decides: CRLF and LF files keep every CR, even a lone one.
    EXPECT_EQ(unix_text("a\r\nb\rc\r\n"), "a\r\nb\rc\r\n");
    EXPECT_EQ(unix_text("a\nb\rc\n"), "a\nb\rc\n");
    EXPECT_EQ(unix_text("no break"), "no break");
    EXPECT_EQ(unix_text(""), "");
}

TEST(TextCheck, ADosEndMarkLastIsNoPartOfTheText) {
    EXPECT_EQ(unix_text("a 1\r\n\x1a"), "a 1\r\n");
    EXPECT_EQ(unix_text("a 1\x1a"), "a 1");
    EXPECT_EQ(unix_text("a\rb\x1a"), "a\nb");
    EXPECT_EQ(unix_text("\x1a"), "");
    // Only as the very last byte: elsewhere it is a control byte, and not text.
    EXPECT_EQ(unix_text("a\x1a\n"), "a\x1a\n");
    EXPECT_EQ(unix_text("a\x1a\x1a"), "a\x1a");
    EXPECT_EQ(first_bad("a\n\x1a\n"), "2 f.txt:2:1: error: this is not a text file: byte 0x1a is a control character at the start of a line\n");
}

// The view is of the text itself unless a copy was needed.
TEST(TextCheck, OnlyClassicMacTextIsCopied) {
    const std::string lf = "a\nb\r\n";
    std::string storage;
    EXPECT_EQ(as_unix_text(lf, storage).data(), lf.data());
    EXPECT_TRUE(storage.empty());
    const std::string mac = "a\rb\r";
    EXPECT_EQ(as_unix_text(mac, storage).data(), storage.data());
}

}  // namespace
}  // namespace raycast
