#include "base/error.h"

#include <cstdarg>
#include <cstdio>

namespace raycast {

namespace {

std::string join_messages(const std::vector<Diagnostic>& diagnostics) {
    std::string text;
    for (const Diagnostic& diagnostic : diagnostics) text += format_diagnostic(diagnostic);
    return text;
}

}  // namespace

std::string format_diagnostic(const Diagnostic& diagnostic) {
    const char* kind = diagnostic.severity == Severity::Error     ? "error"
                       : diagnostic.severity == Severity::Warning ? "warning"
                                                                  : "note";
    const SourceLocation& at = diagnostic.location;
    std::string text = at.file;
    if (at.line > 0) {
        text += string_printf(":%d", at.line);
        if (at.column > 0) text += string_printf(":%d", at.column);
    }
    text += string_printf(": %s: %s\n", kind, diagnostic.message.c_str());
    if (at.line > 0 && at.column > 0 && !diagnostic.source_line.empty()) {
        text += "  " + diagnostic.source_line + "\n  ";
        // Copy tabs from the source line so the caret lines up whatever the tab width.
        const std::string& line = diagnostic.source_line;
        for (int i = 0; i + 1 < at.column && static_cast<size_t>(i) < line.size(); ++i)
            text += line[static_cast<size_t>(i)] == '\t' ? '\t' : ' ';
        text += "^\n";
    }
    return text;
}

bool is_displayable_source_line(std::string_view line) {
    constexpr size_t kMaxShownBytes = 300;
    if (line.size() > kMaxShownBytes) return false;
    for (const char c : line) {
        const unsigned char u = static_cast<unsigned char>(c);
        if (u != '\t' && (u < 0x20 || u == 0x7f)) return false;
    }
    return true;
}

void attach_source_lines(std::vector<Diagnostic>& diagnostics, std::string_view text, const std::string& file) {
    for (Diagnostic& d : diagnostics) {
        if (d.location.file != file || d.location.line <= 0 || !d.source_line.empty()) continue;
        size_t start = 0;
        for (int line = 1; line < d.location.line && start != std::string_view::npos; ++line) {
            start = text.find('\n', start);
            if (start != std::string_view::npos) ++start;
        }
        if (start == std::string_view::npos) continue;
        size_t end = text.find('\n', start);
        if (end == std::string_view::npos) end = text.size();
        if (end > start && text[end - 1] == '\r') --end;
        const std::string_view line = text.substr(start, end - start);
        if (is_displayable_source_line(line)) d.source_line = std::string(line);
    }
}

InputError::InputError(std::vector<Diagnostic> diagnostics)
    : std::runtime_error(join_messages(diagnostics)), diagnostics_(std::move(diagnostics)) {}

InputError::InputError(const std::string& file, const std::string& message)
    : InputError(std::vector<Diagnostic>{Diagnostic{Severity::Error, SourceLocation{file, 0, 0}, message, ""}}) {}

std::string string_printf(const char* format, ...) {
    va_list args;
    va_start(args, format);
    va_list copy;
    va_copy(copy, args);
    const int size = std::vsnprintf(nullptr, 0, format, copy);
    va_end(copy);
    std::string text(size > 0 ? static_cast<size_t>(size) : 0, '\0');
    if (size > 0) std::vsnprintf(text.data(), text.size() + 1, format, args);
    va_end(args);
    return text;
}

}  // namespace raycast
