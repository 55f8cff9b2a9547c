// Errors that reach the user: a located diagnostic (file:line:col: error: message) and the
// exception that carries a batch of them. Entry points: Diagnostic, format_diagnostic, InputError.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>
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

/// Whether a line of an input file may be shown under a diagnostic: text a terminal prints as is
/// (no control bytes but tab), and short enough to read (at most 300 bytes). A line of binary
/// garbage is better left out: the caret display replaces nothing.
bool is_displayable_source_line(std::string_view line);

/// Fills the empty source_line of each diagnostic located at a line of `file` from `text`, the
/// file's content, where that line is displayable.
void attach_source_lines(std::vector<Diagnostic>& diagnostics, std::string_view text, const std::string& file);

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
