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
