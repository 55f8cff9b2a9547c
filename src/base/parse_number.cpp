#include "base/parse_number.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>

namespace raycast {

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Powers of ten that a double holds exactly (10^22 < 2^53 * 2^22 fits the 53-bit significand).
constexpr double kExactPowersOfTen[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                         1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                         1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// Rounding the exact value to double and then to float can differ from rounding it straight to
// float only when the double lands exactly halfway between two floats.
bool is_float_midpoint(double value) {
    const float nearest = static_cast<float>(value);
    if (static_cast<double>(nearest) == value || std::isinf(nearest)) return false;
    const float other = std::nextafter(nearest, value > nearest ? std::numeric_limits<float>::infinity()
                                                                : -std::numeric_limits<float>::infinity());
    const double midpoint = (static_cast<double>(nearest) + static_cast<double>(other)) * 0.5;
    return midpoint == value;
}

// The exact but slower route: the C library's correctly rounded conversion. The program never
// calls setlocale, so strtof sees the "C" locale and its '.' decimal point.
float parse_float_slow(const char* first, const char* last) {
    std::string text(first, last);
    return std::strtof(text.c_str(), nullptr);
}

}  // namespace

NumberResult parse_float(const char* first, const char* last, float& value) {
    const char* p = first;
    bool negative = false;
    if (p != last && (*p == '+' || *p == '-')) negative = *p++ == '-';

    // Keep up to 19 significant digits in an integer; note whether any nonzero digit was dropped.
    uint64_t mantissa = 0;
    int significant_digits = 0;
    int64_t decimal_exponent = 0;
    bool truncated = false;
    bool any_digit = false;
    // Leading zeros add nothing; skipped first, so that the digit loops need not ask (the mantissa
    // is nonzero from the first digit they see, which is not a zero).
    for (; p != last && *p == '0'; ++p) any_digit = true;
    for (; p != last && is_digit(*p); ++p) {
        any_digit = true;
        if (significant_digits < 19) {
            mantissa = mantissa * 10 + static_cast<uint64_t>(*p - '0');
            ++significant_digits;
        } else {
            ++decimal_exponent;
            truncated |= *p != '0';
        }
    }
    if (p != last && *p == '.') {
        const char* after_point = p + 1;
        const char* q = after_point;
        if (mantissa == 0) {  // zeros before the first significant digit only move the point
            for (; q != last && *q == '0'; ++q) {
                any_digit = true;
                --decimal_exponent;
            }
        }
        for (; q != last && is_digit(*q); ++q) {
            any_digit = true;
            if (significant_digits < 19) {
                mantissa = mantissa * 10 + static_cast<uint64_t>(*q - '0');
                ++significant_digits;
                --decimal_exponent;
            } else {
                truncated |= *q != '0';
            }
        }
        if (any_digit) p = q;
    }
    if (!any_digit) return {first, NumberStatus::Invalid};

    if (p != last && (*p == 'e' || *p == 'E')) {
        const char* q = p + 1;
        bool exponent_negative = false;
        if (q != last && (*q == '+' || *q == '-')) exponent_negative = *q++ == '-';
        if (q != last && is_digit(*q)) {
            int64_t exponent = 0;
            // Saturate far beyond anything the digits before the 'e' can offset (a text would need
            // 10^15 leading zeros), so a saturated exponent always means overflow or underflow.
            for (; q != last && is_digit(*q); ++q)
                if (exponent < 1000000000000000) exponent = exponent * 10 + (*q - '0');
            decimal_exponent += exponent_negative ? -exponent : exponent;
            p = q;
        }
        // An 'e' without digits is not part of the number (strtof stops before it too).
    }

    if (mantissa == 0) {
        value = negative ? -0.0f : 0.0f;
        return {p, NumberStatus::Ok};
    }
    // Clinger's fast path: an integer below 2^53 times or over an exact power of ten is
    // correctly rounded by one double operation.
    bool done = false;
    if (!truncated && mantissa <= (uint64_t{1} << 53) && decimal_exponent >= -22 && decimal_exponent <= 22) {
        double exact = static_cast<double>(mantissa);
        exact = decimal_exponent >= 0 ? exact * kExactPowersOfTen[decimal_exponent]
                                      : exact / kExactPowersOfTen[-decimal_exponent];
        if (!is_float_midpoint(exact)) {
            value = static_cast<float>(negative ? -exact : exact);
            done = true;
        }
    }
    if (!done) value = parse_float_slow(first, p);
    if (std::isinf(value)) return {p, NumberStatus::OutOfRange};
    return {p, NumberStatus::Ok};
}

NumberResult parse_int(const char* first, const char* last, int64_t& value) {
    const char* p = first;
    bool negative = false;
    if (p != last && (*p == '+' || *p == '-')) negative = *p++ == '-';
    if (p == last || !is_digit(*p)) return {first, NumberStatus::Invalid};
    // The whole int64_t range: up to 2^63 - 1, or 2^63 when negative.
    const uint64_t limit = negative ? uint64_t{1} << 63 : (uint64_t{1} << 63) - 1;
    uint64_t magnitude = 0;
    bool overflow = false;
    for (; p != last && is_digit(*p); ++p) {
        const uint64_t digit = static_cast<uint64_t>(*p - '0');
        if (overflow || magnitude > (limit - digit) / 10) overflow = true;
        else magnitude = magnitude * 10 + digit;
    }
    if (overflow) return {p, NumberStatus::OutOfRange};
    // Negating in unsigned arithmetic keeps -2^63 defined.
    value = negative ? static_cast<int64_t>(~magnitude + 1) : static_cast<int64_t>(magnitude);
    return {p, NumberStatus::Ok};
}

}  // namespace raycast
