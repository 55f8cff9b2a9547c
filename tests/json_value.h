// A small JSON reader for tests that check what raycast prints (`raycast explain`): enough of
// RFC 8259 to read it back and to refuse anything malformed, with no library to install.
#pragma once

#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace raycast::test {

struct JsonValue {
    enum class Type { Null, Boolean, Number, String, Array, Object };
    Type type = Type::Null;
    bool boolean = false;
    double number = 0;
    std::string string;
    std::vector<JsonValue> array;
    std::map<std::string, JsonValue> object;

    bool has(const std::string& key) const { return type == Type::Object && object.count(key) > 0; }
    const JsonValue& operator[](const std::string& key) const { return object.at(key); }
    const JsonValue& operator[](size_t i) const { return array.at(i); }
};

/// Parses `text` as one JSON value (surrounding whitespace allowed). ok is false, and `error`
/// says where, if it is not valid JSON.
class JsonReader {
public:
    explicit JsonReader(const std::string& text) : text_(text) {}

    bool parse(JsonValue& value) {
        skip_space();
        if (!read_value(value, 0)) return false;
        skip_space();
        if (at_ != text_.size()) return fail("text after the value");
        return true;
    }
    const std::string& error() const { return error_; }

private:
    bool fail(const char* what) {
        if (error_.empty()) error_ = std::string(what) + " at byte " + std::to_string(at_);
        return false;
    }
    void skip_space() {
        while (at_ < text_.size() && (text_[at_] == ' ' || text_[at_] == '\n' || text_[at_] == '\t' || text_[at_] == '\r'))
            ++at_;
    }
    bool literal(const char* word) {
        const std::string w(word);
        if (text_.compare(at_, w.size(), w) != 0) return fail("unknown literal");
        at_ += w.size();
        return true;
    }
    bool read_string(std::string& out) {
        if (text_[at_] != '"') return fail("expected a string");
        ++at_;
        while (at_ < text_.size() && text_[at_] != '"') {
            const char c = text_[at_++];
            if (static_cast<unsigned char>(c) < 0x20) return fail("control character in a string");
            if (c != '\\') {
                out += c;
                continue;
            }
            if (at_ >= text_.size()) return fail("unfinished escape");
            const char e = text_[at_++];
            switch (e) {
                case '"': case '\\': case '/': out += e; break;
                case 'n': out += '\n'; break;
                case 't': out += '\t'; break;
                case 'r': out += '\r'; break;
                case 'b': out += '\b'; break;
                case 'f': out += '\f'; break;
                case 'u':
                    if (at_ + 4 > text_.size()) return fail("short \\u escape");
                    out += static_cast<char>(std::strtol(text_.substr(at_, 4).c_str(), nullptr, 16));
                    at_ += 4;
                    break;
                default: return fail("unknown escape");
            }
        }
        if (at_ >= text_.size()) return fail("unterminated string");
        ++at_;
        return true;
    }
    bool read_value(JsonValue& value, int depth) {
        if (depth > 200) return fail("nested too deep");
        if (at_ >= text_.size()) return fail("expected a value");
        const char c = text_[at_];
        if (c == 'n') return value.type = JsonValue::Type::Null, literal("null");
        if (c == 't') return value.type = JsonValue::Type::Boolean, value.boolean = true, literal("true");
        if (c == 'f') return value.type = JsonValue::Type::Boolean, value.boolean = false, literal("false");
        if (c == '"') return value.type = JsonValue::Type::String, read_string(value.string);
        if (c == '[' || c == '{') {
            const bool is_array = c == '[';
            value.type = is_array ? JsonValue::Type::Array : JsonValue::Type::Object;
            ++at_;
            skip_space();
            if (at_ < text_.size() && text_[at_] == (is_array ? ']' : '}')) return ++at_, true;
            for (;;) {
                skip_space();
                JsonValue item;
                std::string key;
                if (!is_array) {
                    if (at_ >= text_.size() || !read_string(key)) return fail("expected a key");
                    skip_space();
                    if (at_ >= text_.size() || text_[at_] != ':') return fail("expected ':'");
                    ++at_;
                    skip_space();
                    if (value.object.count(key)) return fail("duplicate key");
                }
                if (!read_value(item, depth + 1)) return false;
                if (is_array)
                    value.array.push_back(std::move(item));
                else
                    value.object[key] = std::move(item);
                skip_space();
                if (at_ >= text_.size()) return fail("unterminated array or object");
                if (text_[at_] == ',') {
                    ++at_;
                    continue;
                }
                if (text_[at_] == (is_array ? ']' : '}')) return ++at_, true;
                return fail("expected ',' or a closing bracket");
            }
        }
        // A number: -?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?
        const size_t start = at_;
        if (text_[at_] == '-') ++at_;
        auto digits = [&] {
            const size_t first = at_;
            while (at_ < text_.size() && text_[at_] >= '0' && text_[at_] <= '9') ++at_;
            return at_ > first;
        };
        if (at_ < text_.size() && text_[at_] == '0') {
            ++at_;
        } else if (!digits()) {
            return fail("expected a value");
        }
        if (at_ < text_.size() && text_[at_] == '.') {
            ++at_;
            if (!digits()) return fail("expected digits after '.'");
        }
        if (at_ < text_.size() && (text_[at_] == 'e' || text_[at_] == 'E')) {
            ++at_;
            if (at_ < text_.size() && (text_[at_] == '+' || text_[at_] == '-')) ++at_;
            if (!digits()) return fail("expected an exponent");
        }
        value.type = JsonValue::Type::Number;
        value.number = std::strtod(text_.substr(start, at_ - start).c_str(), nullptr);
        return true;
    }

    const std::string& text_;
    size_t at_ = 0;
    std::string error_;
};

}  // namespace raycast::test
