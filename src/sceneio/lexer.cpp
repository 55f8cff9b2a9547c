#include "sceneio/lexer.h"

#include "sceneio/text_check.h"

namespace raycast {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

bool ends_token(char c) { return is_space(c) || c == '{' || c == '}' || c == '#'; }

}  // namespace

Lexer::Lexer(std::string_view source, std::string file_name) : source_(source), file_name_(std::move(file_name)) {
    // Not part of the first token, nor of the first line's columns (it shows as nothing).
    position_ = line_start_ = byte_order_mark_length(source_);
    next_ = scan();
}

Token Lexer::take() {
    Token token = next_;
    if (token.is("{")) ++depth_;
    if (token.is("}")) --depth_;
    if (!token.is_end()) next_ = scan();
    return token;
}

Token Lexer::scan() {
    for (;;) {
        while (position_ < source_.size() && is_space(source_[position_])) {
            if (source_[position_] == '\n') {
                ++line_;
                line_start_ = position_ + 1;
            }
            ++position_;
        }
        if (position_ < source_.size() && source_[position_] == '#') {
            while (position_ < source_.size() && source_[position_] != '\n') ++position_;
            continue;
        }
        break;
    }
    Token token;
    token.line = line_;
    token.column = static_cast<int>(position_ - line_start_) + 1;
    if (position_ >= source_.size()) return token;
    const size_t start = position_;
    if (source_[position_] == '{' || source_[position_] == '}') {
        ++position_;
    } else if (source_[position_] == '"') {
        // A quoted file name: one token up to the closing quote, spaces, braces and '#' included.
        // Without a closing quote on its line it runs to the end of the line, and the parser says so.
        ++position_;
        while (position_ < source_.size() && source_[position_] != '"' && source_[position_] != '\n' &&
               source_[position_] != '\r')
            ++position_;
        if (position_ < source_.size() && source_[position_] == '"') ++position_;
    } else {
        while (position_ < source_.size() && !ends_token(source_[position_])) ++position_;
    }
    token.text = source_.substr(start, position_ - start);
    return token;
}

std::string_view Lexer::line_text(int line) const {
    // Diagnostics are rare, so a scan from the start is fine.
    size_t start = byte_order_mark_length(source_);
    for (int current = 1; current < line; ++current) {
        const size_t newline = source_.find('\n', start);
        if (newline == std::string_view::npos) return {};
        start = newline + 1;
    }
    size_t end = source_.find('\n', start);
    if (end == std::string_view::npos) end = source_.size();
    if (end > start && source_[end - 1] == '\r') --end;
    return source_.substr(start, end - start);
}

std::string quote_token(std::string_view text) {
    constexpr size_t kMaxShown = 40;
    std::string out = "'";
    for (size_t i = 0; i < text.size() && i < kMaxShown; ++i) {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        if (c < 0x20 || c == 0x7f)
            out += string_printf("\\x%02x", c);
        else
            out += static_cast<char>(c);
    }
    if (text.size() > kMaxShown) out += "...";
    return out + "'";
}

Diagnostic make_diagnostic(const Lexer& lexer, const Token& token, Severity severity, std::string message) {
    Diagnostic diagnostic{severity, lexer.location(token), std::move(message), ""};
    const std::string_view line = lexer.line_text(token.line);
    if (is_displayable_source_line(line)) diagnostic.source_line = std::string(line);
    return diagnostic;
}

}  // namespace raycast
