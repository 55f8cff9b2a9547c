// The rule that tells a text file from a binary one, shared by the scene parser and the OBJ loader
// (docs/scene-format.md, "Files that are not text"): a file is refused when it holds a NUL byte
// anywhere, or when the first byte of a line that is not a blank (space, tab, CR, VT, FF) is a
// control byte or a byte of 0x80 or more that does not begin a valid UTF-8 character.
// Binary files (a zip renamed .obj, an FBX, a PLY with a binary body) break it within their first
// lines; text in any ASCII-compatible encoding keeps it, with anything after a line's first
// character (a comment in GBK or Latin-1, say) left alone. Entry points: find_non_text_byte,
// non_text_problem, non_text_diagnostic.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

#include "base/error.h"

namespace raycast {

/// Whether byte c, first on its line, needs non_text_problem to judge it: a control byte other
/// than the blanks and LF, or a byte of 0x80 or more. One comparison for the usual printable byte.
inline bool is_suspect_line_start(unsigned char c) {
    return c >= 0x7f || (c < 0x20 && c != '\t' && c != '\n' && c != '\r' && c != '\v' && c != '\f');
}

/// Why the byte at p, the first non-blank byte of a line, shows that the file is not text; null
/// when it does not (it begins a valid UTF-8 character). p < end.
const char* non_text_problem(const char* p, const char* end);

/// The length of a UTF-8 byte order mark (EF BB BF) at the start of `text`: 3, or 0 without one.
/// Windows editors may put one first (Notepad, VS Code's "UTF-8 with BOM"); it shows as nothing
/// and is no part of what follows. One comparison when the text starts otherwise.
inline size_t byte_order_mark_length(std::string_view text) {
    return !text.empty() && text[0] == '\xEF' && text.size() >= 3 && text[1] == '\xBB' && text[2] == '\xBF' ? 3 : 0;
}

/// `text` as the parsers read it, with two ways older editors end text taken as Unix's:
/// - a DOS end-of-file mark (Ctrl-Z, 0x1A) as the very last byte, which DOS editors appended, is
///   no part of the text;
/// - a file whose first line break is a CR alone (classic Mac OS, before OS X) has each CR that no
///   LF follows turned into an LF. Read by LF alone it would be one long line: a scene starting
///   with a comment would be all comment. A file whose first line break is CRLF or LF is left as
///   it is (its CRs are blanks).
/// One byte stands for one, so offsets and columns are those of the file. `storage` holds the
/// converted copy when one is needed; otherwise the answer is a view of `text`. One scan to the
/// first line break for other text.
std::string_view as_unix_text(std::string_view text, std::string& storage);

/// The offset of the first byte of `text` that breaks the rule, if any.
std::optional<size_t> find_non_text_byte(std::string_view text);

/// The error for the byte at `offset` of `text` (which breaks the rule), located at its line and
/// column: "this is not a text file: byte 0x00 (NUL) never appears in text". It shows no source
/// line: that line holds the byte, which a terminal cannot show.
Diagnostic non_text_diagnostic(std::string_view text, size_t offset, const std::string& file_name);

}  // namespace raycast
