#include "sceneio/text_check.h"

#include <algorithm>
#include <cstring>

#include "base/check.h"

namespace raycast {

namespace {

bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

bool is_continuation(const char* p, const char* end, unsigned char low = 0x80, unsigned char high = 0xbf) {
    if (p >= end) return false;
    const unsigned char c = static_cast<unsigned char>(*p);
    return c >= low && c <= high;
}

// Whether a valid UTF-8 character (RFC 3629: no overlong forms, no surrogates, nothing past
// U+10FFFF) begins at p, whose byte is 0x80 or more.
bool begins_utf8_character(const char* p, const char* end) {
    const unsigned char lead = static_cast<unsigned char>(*p);
    if (lead >= 0xc2 && lead <= 0xdf) return is_continuation(p + 1, end);
    if (lead >= 0xe0 && lead <= 0xef) {
        const unsigned char low = lead == 0xe0 ? 0xa0 : 0x80;   // not overlong
        const unsigned char high = lead == 0xed ? 0x9f : 0xbf;  // not a surrogate
        return is_continuation(p + 1, end, low, high) && is_continuation(p + 2, end);
    }
    if (lead >= 0xf0 && lead <= 0xf4) {
        const unsigned char low = lead == 0xf0 ? 0x90 : 0x80;   // not overlong
        const unsigned char high = lead == 0xf4 ? 0x8f : 0xbf;  // at most U+10FFFF
        return is_continuation(p + 1, end, low, high) && is_continuation(p + 2, end) && is_continuation(p + 3, end);
    }
    return false;  // a continuation byte, 0xc0, 0xc1 (overlong) or 0xf5 and above
}

}  // namespace

const char* non_text_problem(const char* p, const char* end) {
    const unsigned char c = static_cast<unsigned char>(*p);
    if (!is_suspect_line_start(c)) return nullptr;
    if (c < 0x80) return "is a control character at the start of a line";
    if (begins_utf8_character(p, end)) return nullptr;
    return "at the start of a line does not begin a UTF-8 character";
}

std::string_view as_unix_text(std::string_view text, std::string& storage) {
    if (!text.empty() && text.back() == '\x1a') text.remove_suffix(1);
    const size_t first_break = text.find_first_of("\r\n");
    const bool classic_mac =
        first_break != std::string_view::npos && text[first_break] == '\r' &&
        (first_break + 1 == text.size() || text[first_break + 1] != '\n');
    if (!classic_mac) return text;
    storage.assign(text);
    for (size_t i = first_break; i < storage.size(); ++i)
        if (storage[i] == '\r' && (i + 1 == storage.size() || storage[i + 1] != '\n')) storage[i] = '\n';
    return storage;
}

std::optional<size_t> find_non_text_byte(std::string_view text) {
    const char* begin = text.data();
    const char* end = begin + text.size();
    const void* nul = std::memchr(begin, 0, text.size());
    // Line starts past the first NUL cannot be the first bad byte.
    const char* limit = nul ? static_cast<const char*>(nul) : end;
    for (const char* p = begin; p < limit;) {
        while (p < limit && is_blank(*p)) ++p;
        if (p == limit) break;
        if (non_text_problem(p, end)) return static_cast<size_t>(p - begin);
        const void* newline = std::memchr(p, '\n', static_cast<size_t>(limit - p));
        if (!newline) break;
        p = static_cast<const char*>(newline) + 1;
    }
    if (nul) return static_cast<size_t>(limit - begin);
    return std::nullopt;
}

Diagnostic non_text_diagnostic(std::string_view text, size_t offset, const std::string& file_name) {
    const char* begin = text.data();
    const char* at = begin + offset;
    const unsigned char byte = static_cast<unsigned char>(*at);
    size_t line_start = offset;
    while (line_start > 0 && begin[line_start - 1] != '\n') --line_start;
    constexpr size_t kIntMax = 0x7fffffff;
    // No source line: the line holds the byte, which a terminal cannot show (make_diagnostic's rule).
    Diagnostic d;
    d.location.file = file_name;
    d.location.line = static_cast<int>(std::min(1 + static_cast<size_t>(std::count(begin, at, '\n')), kIntMax));
    d.location.column = static_cast<int>(std::min(offset - line_start + 1, kIntMax));
    const char* problem = byte == 0 ? "(NUL) never appears in text" : non_text_problem(at, begin + text.size());
    RAYCAST_CHECK(problem != nullptr);
    d.message = string_printf("this is not a text file: byte 0x%02x %s", byte, problem);
    // UTF-16 (Notepad's "Unicode", PowerShell's '>') is text, just not in a form raycast reads:
    // its byte order mark says so.
    if (text.size() >= 2 && ((begin[0] == '\xFF' && begin[1] == '\xFE') || (begin[0] == '\xFE' && begin[1] == '\xFF')))
        d.message += ": the file is UTF-16 text (Notepad's \"Unicode\"); save it as UTF-8";
    return d;
}

}  // namespace raycast
