// Locale-independent number parsing for the scene lexer and the OBJ loader.
// parse_float gives the same correctly rounded float that strtof gives in the C locale.
#pragma once

#include <cstdint>

namespace raycast {

enum class NumberStatus {
    Ok,
    Invalid,     ///< no number at the start of the text
    OutOfRange,  ///< a number, but too large for the type (floats: beyond FLT_MAX)
};

struct NumberResult {
    const char* end;  ///< one past the last character used; equals `first` when Invalid
    NumberStatus status;
};

/// Reads a decimal float: [+-] digits [. digits] [(e|E) [+-] digits], digits on at least one
/// side of the point. No inf, nan, hex or leading whitespace. Values too small for a float
/// round to zero, as strtof does.
NumberResult parse_float(const char* first, const char* last, float& value);

/// Reads a decimal integer: [+-] digits.
NumberResult parse_int(const char* first, const char* last, int64_t& value);

}  // namespace raycast
