// Splits scene text into tokens the way the course's parser reads them (whitespace-separated,
// so CRLF and tabs are fine), with two additions: braces are always tokens of their own
// (`shininess 20}` works, as it does with the course's "%f"), `#` starts a comment that runs
// to the end of the line, and a double-quoted string ("mesh/my model.obj") is one token, quotes
// included. Every token knows its line and column.
#pragma once

#include <string>
#include <string_view>

#include "base/error.h"

namespace raycast {

struct Token {
    std::string_view text;  ///< empty at the end of the input
    int line = 0;
    int column = 0;

    bool is_end() const { return text.empty(); }
    bool is(std::string_view s) const { return text == s; }
};

class Lexer {
public:
    Lexer(std::string_view source, std::string file_name);

    /// The next token, without consuming it.
    const Token& peek() const { return next_; }
    /// Consumes and returns the next token; at the end it keeps returning the end token.
    Token take();
    /// How many braces are open after the tokens taken so far.
    int depth() const { return depth_; }

    const std::string& file_name() const { return file_name_; }
    SourceLocation location(const Token& token) const { return {file_name_, token.line, token.column}; }
    /// The text of a line (1-based) without its line break, for diagnostics.
    std::string_view line_text(int line) const;

private:
    Token scan();

    std::string_view source_;
    std::string file_name_;
    size_t position_ = 0;
    int line_ = 1;
    size_t line_start_ = 0;
    int depth_ = 0;
    Token next_;
};

/// A token as it should appear in a message: quoted, control bytes escaped, long ones cut.
std::string quote_token(std::string_view text);

/// A diagnostic at a token, with its line's text for the caret display.
Diagnostic make_diagnostic(const Lexer& lexer, const Token& token, Severity severity, std::string message);

}  // namespace raycast
