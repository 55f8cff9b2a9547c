// Errors that reach the user: a located diagnostic (file:line:col: error: message) and the
// exception that carries a batch of them. Entry points: Diagnostic, format_diagnostic, InputError.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace raycast {

/// A place in an input file; line and column count from 1, a column counts bytes.
struct SourceLocation {
    std::string file;
    int line = 0;
    int column = 0;
};

enum class Severity { Error, Warning, Note };

/// One message about an input file, with the text of the offending line for the caret display.
struct Diagnostic {
    Severity severity = Severity::Error;
    SourceLocation location;
    std::string message;
    std::string source_line;  ///< the whole line at location.line, without its newline; may be empty
};

/// "file:line:col: error: message", then the source line and a caret under the column when known.
/// A location without a line prints as "file: error: message".
std::string format_diagnostic(const Diagnostic& diagnostic);

/// Thrown for anything wrong with the user's input or output files. Never for programming errors.
class InputError : public std::runtime_error {
public:
    explicit InputError(std::vector<Diagnostic> diagnostics);
    /// A single error about a file as a whole (cannot open, cannot write).
    InputError(const std::string& file, const std::string& message);

    const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

private:
    std::vector<Diagnostic> diagnostics_;
};

/// Builds a printf-style string; the project's stand-in for std::format (GCC 12 has none).
std::string string_printf(const char* format, ...) __attribute__((format(printf, 1, 2)));

}  // namespace raycast
