// Tests for parse_float and parse_int (base/parse_number.h): the scene lexer, the OBJ loader and
// the command line read every number through them, so a wrong rounding or a wrongly accepted
// token shows up everywhere. parse_float is checked bit for bit against strtof in the "C" locale
// (the header's promise) on many random decimal strings, midpoints between floats and hand-picked
// hard cases; the grammar (what is rejected, where parsing stops) is checked by hand.
#include "base/parse_number.h"

#include <gtest/gtest.h>

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <string>

namespace raycast {
namespace {

uint32_t bits_of(float f) {
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return bits;
}

struct FloatParse {
    NumberStatus status;
    size_t used;  // characters consumed
    float value;
};

FloatParse parse_f(const std::string& text) {
    float value = 12345.0f;  // a sentinel that no test expects
    const NumberResult r = parse_float(text.data(), text.data() + text.size(), value);
    return {r.status, static_cast<size_t>(r.end - text.data()), value};
}

struct IntParse {
    NumberStatus status;
    size_t used;
    int64_t value;
};

IntParse parse_i(const std::string& text) {
    int64_t value = 777;
    const NumberResult r = parse_int(text.data(), text.data() + text.size(), value);
    return {r.status, static_cast<size_t>(r.end - text.data()), value};
}

// The reference: strtof on the same text (tests never call setlocale, so this is the C locale).
// Returns the float, and how many characters strtof used.
float reference(const std::string& text, size_t* used = nullptr) {
    char* end = nullptr;
    errno = 0;
    const float value = std::strtof(text.c_str(), &end);
    if (used) *used = static_cast<size_t>(end - text.c_str());
    return value;
}

// A text that the grammar accepts in full must give strtof's float, bit for bit, and use all of it.
void expect_like_strtof(const std::string& text) {
    size_t strtof_used = 0;
    const float expected = reference(text, &strtof_used);
    ASSERT_EQ(strtof_used, text.size()) << "test bug: strtof does not read all of " << text;
    const FloatParse got = parse_f(text);
    EXPECT_EQ(got.used, text.size()) << text;
    if (std::isinf(expected)) {
        EXPECT_EQ(got.status, NumberStatus::OutOfRange) << text;
    } else {
        EXPECT_EQ(got.status, NumberStatus::Ok) << text;
        EXPECT_EQ(bits_of(got.value), bits_of(expected))
            << text << ": got " << got.value << " (" << std::hexfloat << got.value << "), strtof gives " << expected
            << " (" << expected << ")" << std::defaultfloat;
    }
}

TEST(ParseFloat, HandPickedValuesMatchStrtofBitForBit) {
    for (const char* text :
         {"0", "1", "-1", "+1", "0.1", "-.16", ".5", "1.", "+.5", "-0.0", "3.14159265358979323846",
          "1e-45",             // the smallest subnormal float, rounded from below
          "1.4e-45", "7e-46", "8e-46",  // half the smallest subnormal is 7.006e-46: 7e-46 → 0, 8e-46 → 2^-149
          "1.17549435e-38",    // FLT_MIN
          "1.1754942e-38",     // the largest subnormal
          "3.4028235e38",      // FLT_MAX as printed
          "3.40282346638528859811704183484516925440e+38",  // FLT_MAX exactly
          "340282356779733661637539395458142568447",       // just below the overflow midpoint: FLT_MAX
          "16777216", "16777217", "16777218", "16777219",  // around 2^24, where floats are 2 apart
          "0.000000000000000000000000000000000000000000001", "123456789012345678901234567890",
          "1234567890123456789.5", "0.30000000000000001665", "2.5e-7", "1E10", "1e+10", "1e-0",
          "00000001.50000000000", "9007199254740993", "1e22", "1e23", "1e-22", "1e-23", "4.2e22"}) {
        SCOPED_TRACE(text);
        expect_like_strtof(text);
    }
}

TEST(ParseFloat, SimpleValuesAreExact) {
    // Values a person can check: each is a float exactly, or the float nearest to the decimal.
    EXPECT_EQ(parse_f("0.5").value, 0.5f);
    EXPECT_EQ(parse_f("-.16").value, -0.16f);
    EXPECT_EQ(parse_f("1.").value, 1.0f);
    EXPECT_EQ(parse_f("+2.25").value, 2.25f);
    EXPECT_EQ(parse_f("0.1").value, 0.1f);
    EXPECT_EQ(parse_f("1e3").value, 1000.0f);
    EXPECT_EQ(parse_f("25E-2").value, 0.25f);
    // 16777217 = 2^24 + 1 lies halfway between the floats 2^24 and 2^24 + 2: ties go to the even
    // significand, 2^24. Just above the midpoint it must round up.
    EXPECT_EQ(parse_f("16777217").value, 16777216.0f);
    EXPECT_EQ(parse_f("16777217.000000000000000000001").value, 16777218.0f);
    EXPECT_EQ(parse_f("16777219").value, 16777220.0f);  // midpoint of 2^24+2, 2^24+4: even is 2^24+4
    // The smallest subnormal, 2^-149 = 1.401298e-45.
    EXPECT_EQ(parse_f("1e-45").value, std::numeric_limits<float>::denorm_min());
    EXPECT_EQ(parse_f("3.4028235e38").value, FLT_MAX);
}

TEST(ParseFloat, NegativeZeroKeepsItsSign) {
    const FloatParse r = parse_f("-0.000");
    EXPECT_EQ(r.status, NumberStatus::Ok);
    EXPECT_EQ(r.value, 0.0f);
    EXPECT_TRUE(std::signbit(r.value));
    EXPECT_FALSE(std::signbit(parse_f("0e99999").value));
}

TEST(ParseFloat, UnderflowRoundsToZeroAndIsNotAnError) {
    // Header: values too small for a float round to zero, as strtof does: 5e-324 (the smallest
    // double), and 7e-46, which is just below 7.006e-46, half the smallest float 2^-149.
    for (const char* text : {"5e-324", "1e-50", "7e-46", "-1e-300", "0.1e-9999999999"}) {
        SCOPED_TRACE(text);
        const FloatParse r = parse_f(text);
        EXPECT_EQ(r.status, NumberStatus::Ok);
        EXPECT_EQ(r.used, std::strlen(text));
        EXPECT_EQ(r.value, 0.0f);
        EXPECT_EQ(std::signbit(r.value), text[0] == '-');
    }
    EXPECT_EQ(parse_f("8e-46").value, std::numeric_limits<float>::denorm_min());
    EXPECT_EQ(parse_f("7.01e-46").value, std::numeric_limits<float>::denorm_min());
}

TEST(ParseFloat, OverflowIsOutOfRangeButConsumesTheNumber) {
    // 3.4028236e38 is past the midpoint (3.40282357e38) between FLT_MAX and 2^128, so it overflows.
    for (const char* text : {"1e39", "-1e39", "3.4028236e38", "1e99999999999", "99999999999999999999999999999999999999999"}) {
        SCOPED_TRACE(text);
        const FloatParse r = parse_f(text);
        EXPECT_EQ(r.status, NumberStatus::OutOfRange);
        EXPECT_EQ(r.used, std::strlen(text));
    }
}

TEST(ParseFloat, RejectsTextsWithoutANumberAtTheStart) {
    // Header: no inf, nan, hex or leading whitespace; digits on at least one side of the point.
    for (const char* text : {"", "-", "+", ".", "-.", "+.e5", "e5", "E5", ".e1", "nan", "NaN", "inf", "-inf",
                             "infinity", " 1", "\t1", "\n1", "x1", "--1", "+-1", "abc"}) {
        SCOPED_TRACE(std::string("'") + text + "'");
        const FloatParse r = parse_f(text);
        EXPECT_EQ(r.status, NumberStatus::Invalid);
        EXPECT_EQ(r.used, 0u);  // end == first when Invalid
    }
}

TEST(ParseFloat, StopsAtTheFirstCharacterThatIsNotPartOfTheNumber) {
    struct Case {
        const char* text;
        size_t used;
        float value;
    };
    for (const Case& c : {Case{"1.2.3", 3, 1.2f}, Case{"1e", 1, 1.0f}, Case{"1e+", 1, 1.0f}, Case{"2E-x", 1, 2.0f},
                          Case{"1.5e10x", 6, 1.5e10f}, Case{"0x10", 1, 0.0f},  // hex: only the 0 is a number
                          Case{"12abc", 2, 12.0f}, Case{"-3,5", 2, -3.0f}, Case{"4 5", 1, 4.0f},
                          Case{"1.e5", 4, 1e5f}, Case{"1..5", 2, 1.0f}, Case{"7.5e+2.0", 6, 750.0f},
                          Case{"5-3", 1, 5.0f}, Case{"1infinity", 1, 1.0f}}) {
        SCOPED_TRACE(c.text);
        const FloatParse r = parse_f(c.text);
        EXPECT_EQ(r.status, NumberStatus::Ok);
        EXPECT_EQ(r.used, c.used);
        EXPECT_EQ(r.value, c.value);
        size_t strtof_used = 0;
        if (std::strncmp(c.text, "0x", 2) != 0 && std::strcmp(c.text, "1infinity") != 0) {
            reference(c.text, &strtof_used);
            EXPECT_EQ(strtof_used, c.used) << "strtof stops elsewhere";
        }
    }
}

TEST(ParseFloat, NeverReadsPastLast) {
    // The text continues in memory past `last`; those characters must not change the result.
    const std::string text = "123456e7";
    float value = 0;
    NumberResult r = parse_float(text.data(), text.data() + 3, value);
    EXPECT_EQ(r.status, NumberStatus::Ok);
    EXPECT_EQ(r.end, text.data() + 3);
    EXPECT_EQ(value, 123.0f);

    const std::string exp = "1.5e10";
    r = parse_float(exp.data(), exp.data() + 4, value);  // "1.5e": the e has no digits in range
    EXPECT_EQ(r.end, exp.data() + 3);
    EXPECT_EQ(value, 1.5f);
    r = parse_float(exp.data(), exp.data() + 5, value);  // "1.5e1"
    EXPECT_EQ(r.end, exp.data() + 5);
    EXPECT_EQ(value, 15.0f);

    // A long text, cut inside: the slow (strtof) path must see only [first, last) too.
    const std::string long_text = "1.0000000000000000000000000000001999999";
    r = parse_float(long_text.data(), long_text.data() + 33, value);
    EXPECT_EQ(r.end, long_text.data() + 33);
    EXPECT_EQ(value, 1.0f);
    const std::string midpoint = "16777217999";  // cut to "16777217": the midpoint, rounds down to even
    r = parse_float(midpoint.data(), midpoint.data() + 8, value);
    EXPECT_EQ(r.end, midpoint.data() + 8);
    EXPECT_EQ(value, 16777216.0f);

    r = parse_float(text.data(), text.data(), value);
    EXPECT_EQ(r.status, NumberStatus::Invalid);
}

// Random decimal strings: 1 to 9 significant digits (sometimes more), a point anywhere (or none),
// an optional sign and exponent, over the whole float range and past both ends of it.
std::string random_decimal(std::mt19937& rng) {
    std::uniform_int_distribution<int> digit(0, 9), coin(0, 1), percent(0, 99);
    const int digit_count = percent(rng) < 85 ? std::uniform_int_distribution<int>(1, 9)(rng)
                                              : std::uniform_int_distribution<int>(10, 30)(rng);
    std::string digits;
    for (int i = 0; i < digit_count; ++i) digits += static_cast<char>('0' + digit(rng));
    if (percent(rng) < 20) digits.insert(0, std::string(static_cast<size_t>(percent(rng) % 6), '0'));
    std::string text;
    const int sign = percent(rng);
    if (sign < 30) text += '-';
    else if (sign < 40) text += '+';
    const int point = std::uniform_int_distribution<int>(-1, static_cast<int>(digits.size()))(rng);
    if (point < 0) {
        text += digits;
    } else {
        text += digits.substr(0, static_cast<size_t>(point)) + "." + digits.substr(static_cast<size_t>(point));
    }
    if (percent(rng) < 70) {
        text += coin(rng) ? 'e' : 'E';
        const int e_sign = percent(rng);
        if (e_sign < 45) text += '-';
        else if (e_sign < 55) text += '+';
        text += std::to_string(std::uniform_int_distribution<int>(0, 50)(rng));
    }
    return text;
}

TEST(ParseFloat, RandomDecimalsMatchStrtofBitForBit) {
    std::mt19937 rng(20240611);
    int checked = 0;
    for (int i = 0; i < 200000; ++i) {
        const std::string text = random_decimal(rng);
        size_t strtof_used = 0;
        reference(text, &strtof_used);
        if (strtof_used != text.size()) continue;  // e.g. "-." : not a number for either
        expect_like_strtof(text);
        ++checked;
        if (HasFailure()) return;  // one report is enough
    }
    EXPECT_GT(checked, 150000);
}

TEST(ParseFloat, MidpointsBetweenFloatsRoundToEvenLikeStrtof) {
    // Decimal texts that are exactly halfway between two neighbouring floats (and a hair either
    // side): where a double-then-float rounding goes wrong. "%.40g" prints the double midpoint,
    // which has at most 25 significant bits, exactly (it is an integer or has few decimals here).
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> decade(0.0, 12.0);  // floats from 1 to 10^12
    for (int i = 0; i < 20000; ++i) {
        const float low = static_cast<float>(std::pow(10.0, decade(rng)));
        const float high = std::nextafter(low, std::numeric_limits<float>::infinity());
        const double mid = (static_cast<double>(low) + static_cast<double>(high)) / 2;
        char buffer[128];
        std::snprintf(buffer, sizeof buffer, "%.40g", mid);
        std::string text = buffer;
        // Trim trailing zeros after a point, which %g with a huge precision may leave.
        if (text.find('.') != std::string::npos) {
            while (text.back() == '0') text.pop_back();
            if (text.back() == '.') text.pop_back();
        }
        ASSERT_EQ(std::strtod(text.c_str(), nullptr), mid) << "test bug: not the exact midpoint: " << text;
        const float even = (bits_of(low) & 1u) == 0 ? low : high;
        EXPECT_EQ(parse_f(text).value, even) << text;
        expect_like_strtof(text);
        const std::string above = text + (text.find('.') == std::string::npos ? ".0000000000000000000000001" : "0000000000000000000000001");
        EXPECT_EQ(parse_f(above).value, high) << above;
        expect_like_strtof(above);
        if (HasFailure()) return;
    }
}

TEST(ParseFloat, ManyDigitsAndLongRunsOfZeros) {
    // 10^400 · 10^-400 = 1; 0.(300 zeros)1 · 10^301 = 1; a 25-digit mantissa whose dropped
    // digits decide the rounding of 1 + 2^-24 (the midpoint between 1 and 1 + 2^-23).
    const std::string ten_to_400 = "1" + std::string(400, '0') + "e-400";
    EXPECT_EQ(parse_f(ten_to_400).value, 1.0f);
    expect_like_strtof(ten_to_400);
    const std::string tiny = "0." + std::string(300, '0') + "1e301";
    EXPECT_EQ(parse_f(tiny).value, 1.0f);
    expect_like_strtof(tiny);
    // 1 + 2^-24 = 1.000000059604644775390625 exactly: the midpoint, ties to even (1.0).
    EXPECT_EQ(parse_f("1.000000059604644775390625").value, 1.0f);
    EXPECT_EQ(parse_f("1.0000000596046447753906250000000001").value, std::nextafter(1.0f, 2.0f));
    EXPECT_EQ(parse_f("1.0000000596046447753906249999999999").value, 1.0f);
}

TEST(ParseFloat, LeadingZerosAreNotSignificantDigits) {
    // Zeros before the first nonzero digit, before or after the point, only place it: a mantissa
    // keeps 19 significant digits, and none of them may go to those zeros.
    const std::string zeros(30, '0');
    EXPECT_EQ(parse_f(zeros + "1.5").value, 1.5f);
    EXPECT_EQ(parse_f("0." + zeros + "125e31").value, 1.25f);
    EXPECT_EQ(parse_f(zeros + "." + zeros + "3e31").value, 3.0f);
    const std::string texts[] = {zeros + "1.5", zeros + "16777217.5", zeros + "1234567890123456789.5e-18",
                                 "0." + zeros + "125e31", zeros + "." + zeros + "3e31",
                                 "000", "0.000", "-00.0", "00.5", ".05"};
    for (const std::string& text : texts) expect_like_strtof(text);
}

TEST(ParseFloat, HugeExponentWithManyDigitsMatchesStrtof) {
    // 10^100009 · 10^-1000000 is far below the smallest float: 0, as strtof says.
    const std::string small = "1" + std::string(100009, '0') + "e-1000000";
    EXPECT_EQ(reference(small), 0.0f);
    const FloatParse r = parse_f(small);
    EXPECT_EQ(r.status, NumberStatus::Ok);
    EXPECT_EQ(r.used, small.size());
    EXPECT_EQ(r.value, 0.0f);
}

// 0.(99989 zeros)1 · 10^1000000 = 10^900010: far beyond FLT_MAX, so strtof gives inf and
// parse_float must say OutOfRange. The text is ~100 KB, unusual but valid; a parser that caps the
// exponent while reading it (here at 100000, which the 99990 leading zeros bring back to 10^10)
// must not then take its fast path and return 1e10.
TEST(ParseFloat, HugeExponentAfterManyLeadingZerosOverflows) {
    const std::string large = "0." + std::string(99989, '0') + "1e1000000";
    EXPECT_TRUE(std::isinf(reference(large)));
    const FloatParse r = parse_f(large);
    EXPECT_EQ(r.status, NumberStatus::OutOfRange) << "parsed as " << r.value;
    EXPECT_EQ(r.used, large.size());
}

TEST(ParseInt, ReadsSignedDecimalIntegers) {
    struct Case {
        const char* text;
        int64_t value;
        size_t used;
    };
    for (const Case& c : {Case{"0", 0, 1}, Case{"42", 42, 2}, Case{"-42", -42, 3}, Case{"+7", 7, 2},
                          Case{"007", 7, 3}, Case{"-0", 0, 2}, Case{"12abc", 12, 2}, Case{"1.5", 1, 1},
                          Case{"3e5", 3, 1}, Case{"-5/6", -5, 2}, Case{"2147483648", 2147483648LL, 10},
                          Case{"4611686018427387904", int64_t{1} << 62, 19},
                          Case{"-4611686018427387904", -(int64_t{1} << 62), 20}}) {
        SCOPED_TRACE(c.text);
        const IntParse r = parse_i(c.text);
        EXPECT_EQ(r.status, NumberStatus::Ok);
        EXPECT_EQ(r.value, c.value);
        EXPECT_EQ(r.used, c.used);
    }
}

TEST(ParseInt, RejectsTextsWithoutDigitsAtTheStart) {
    for (const char* text : {"", "-", "+", " 1", "a1", "--1", "+-1", ".5", "e5", "\t3"}) {
        SCOPED_TRACE(std::string("'") + text + "'");
        const IntParse r = parse_i(text);
        EXPECT_EQ(r.status, NumberStatus::Invalid);
        EXPECT_EQ(r.used, 0u);
    }
}

TEST(ParseInt, NumbersFarTooLargeAreOutOfRangeAndConsumed) {
    for (const char* text : {"99999999999999999999", "-99999999999999999999", "123456789012345678901234567890"}) {
        SCOPED_TRACE(text);
        const IntParse r = parse_i(text);
        EXPECT_EQ(r.status, NumberStatus::OutOfRange);
        EXPECT_EQ(r.used, std::strlen(text));
    }
}

// 20000000000000000000 (2·10^19) exceeds even uint64_t (1.8·10^19). It must be OutOfRange, never
// a wrapped-around value such as 2·10^19 − 2^64 = 1553255926290448384.
TEST(ParseInt, TwentyDigitNumbersDoNotWrapAround) {
    for (const char* text : {"20000000000000000000", "-20000000000000000000", "18446744073709551617",
                             "23000000000000000000"}) {
        SCOPED_TRACE(text);
        const IntParse r = parse_i(text);
        EXPECT_EQ(r.status, NumberStatus::OutOfRange) << "parsed as " << r.value;
        EXPECT_EQ(r.used, std::strlen(text));
    }
}

// Header: OutOfRange means "too large for the type", and the type is int64_t: every int64_t must
// parse, and one past either end must not.
TEST(ParseInt, AcceptsTheWholeInt64Range) {
    IntParse r = parse_i("9223372036854775807");
    EXPECT_EQ(r.status, NumberStatus::Ok);
    EXPECT_EQ(r.value, std::numeric_limits<int64_t>::max());
    r = parse_i("-9223372036854775808");
    EXPECT_EQ(r.status, NumberStatus::Ok);
    EXPECT_EQ(r.value, std::numeric_limits<int64_t>::min());
    r = parse_i("4611686018427387905");  // 2^62 + 1
    EXPECT_EQ(r.status, NumberStatus::Ok);
    EXPECT_EQ(r.value, (int64_t{1} << 62) + 1);
    EXPECT_EQ(parse_i("9223372036854775808").status, NumberStatus::OutOfRange);
    EXPECT_EQ(parse_i("-9223372036854775809").status, NumberStatus::OutOfRange);
}

TEST(ParseInt, NeverReadsPastLast) {
    const std::string text = "12345";
    int64_t value = 0;
    const NumberResult r = parse_int(text.data(), text.data() + 2, value);
    EXPECT_EQ(r.status, NumberStatus::Ok);
    EXPECT_EQ(r.end, text.data() + 2);
    EXPECT_EQ(value, 12);
    EXPECT_EQ(parse_int(text.data(), text.data(), value).status, NumberStatus::Invalid);
}

}  // namespace
}  // namespace raycast
