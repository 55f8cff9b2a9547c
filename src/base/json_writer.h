// A small JSON writer for what raycast prints (`raycast explain`) and serves (the viewer's
// /status and /explain): objects and arrays with two-space indentation (at most 16 levels deep), numbers that read back as
// the same float, strings escaped as RFC 8259 requires. No reader: raycast never parses JSON.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <vector>

namespace raycast {

class JsonWriter {
public:
    /// The text written so far; the writer is empty afterwards.
    std::string take() { return std::move(out_); }

    /// Opens an object ('{') or array ('['); close() with the matching bracket.
    void open(char bracket) {
        out_ += bracket;
        first_.push_back(true);
    }
    void close(char bracket) {
        const bool empty = first_.back();
        first_.pop_back();
        if (!empty) newline();
        out_ += bracket;
    }
    /// Starts a member of an object: the value comes next.
    void key(const char* name) {
        item();
        string(name);
        out_ += ": ";
    }
    /// Starts an element of an array.
    void item() {
        if (!first_.back()) out_ += ',';
        first_.back() = false;
        newline();
    }

    /// %.9g reads back as the same float; infinity and NaN, which JSON cannot hold, as null.
    void number(double x) {
        if (!std::isfinite(x)) {
            out_ += "null";
            return;
        }
        char text[32];
        std::snprintf(text, sizeof text, "%.9g", x);
        out_ += text;
    }
    void integer(long long x) { out_ += std::to_string(x); }
    void boolean(bool b) { out_ += b ? "true" : "false"; }
    void null() { out_ += "null"; }
    void string(const std::string& s) {
        out_ += '"';
        for (const char c : s) {
            if (c == '"' || c == '\\') {
                out_ += '\\';
                out_ += c;
            } else if (static_cast<unsigned char>(c) < 0x20) {
                char escaped[8];
                std::snprintf(escaped, sizeof escaped, "\\u%04x", static_cast<unsigned>(static_cast<unsigned char>(c)));
                out_ += escaped;
            } else {
                out_ += c;
            }
        }
        out_ += '"';
    }
    /// A short array of numbers on one line.
    void inline_numbers(std::initializer_list<double> values) {
        out_ += '[';
        bool first = true;
        for (const double v : values) {
            if (!first) out_ += ", ";
            first = false;
            number(v);
        }
        out_ += ']';
    }

    void numbers_field(const char* name, std::initializer_list<double> values) { key(name), inline_numbers(values); }
    void field(const char* name, double x) { key(name), number(x); }
    void field(const char* name, bool b) { key(name), boolean(b); }
    void field(const char* name, const std::string& s) { key(name), string(s); }
    void integer_field(const char* name, long long x) { key(name), integer(x); }

private:
    // Indented by nesting, up to kMaxIndentLevels: a ray tree nests two levels a bounce, and
    // indentation by the full depth made a deep tree's text grow with its depth squared (93% of
    // a 421 MB explanation was spaces).
    static constexpr size_t kMaxIndentLevels = 16;
    void newline() {
        out_ += '\n';
        out_.append(2 * std::min(first_.size(), kMaxIndentLevels), ' ');
    }

    std::string out_;
    std::vector<bool> first_;  // per open bracket: nothing written in it yet
};

}  // namespace raycast
