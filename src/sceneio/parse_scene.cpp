#include "sceneio/parse_scene.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <initializer_list>
#include <optional>

#include "base/limits.h"
#include "base/parallel.h"
#include "base/parse_number.h"
#include "geometry/triangle.h"
#include "sceneio/lexer.h"
#include "sceneio/text_check.h"

namespace raycast {

namespace {

const char* const kTopLevelKeywords[] = {"PerspectiveCamera", "OrthographicCamera", "Background",
                                         "Lights",            "Materials",          "Group"};
const char* const kObjectKeywords[] = {"Group",        "Sphere",    "Plane",       "Triangle",     "TriangleMesh",
                                       "Transform",    "RevSurface", "BezierCurve", "BsplineCurve"};
const char* const kTransformItems[] = {"Scale",   "UniformScale", "Translate", "XRotate", "YRotate",
                                       "ZRotate", "Rotate",       "Matrix4f",  "Matrix"};

template <size_t N>
bool is_one_of(std::string_view word, const char* const (&list)[N]) {
    return std::find(std::begin(list), std::end(list), word) != std::end(list);
}

// Levenshtein distance, for "did you mean" hints.
size_t edit_distance(std::string_view a, std::string_view b) {
    std::vector<size_t> row(b.size() + 1);
    for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
    for (size_t i = 1; i <= a.size(); ++i) {
        size_t diagonal = row[0];
        row[0] = i;
        for (size_t j = 1; j <= b.size(); ++j) {
            const size_t above = row[j];
            const bool same = std::tolower(static_cast<unsigned char>(a[i - 1])) ==
                              std::tolower(static_cast<unsigned char>(b[j - 1]));
            row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
            diagonal = above;
        }
    }
    return row[b.size()];
}

// "; did you mean 'Sphere'?" when one candidate is close, else ": expected A, B or C".
std::string suggestion(std::string_view word, const std::vector<std::string>& candidates) {
    const std::string* best = nullptr;
    size_t best_distance = 0;
    for (const std::string& candidate : candidates) {
        const size_t distance = edit_distance(word, candidate);
        if (!best || distance < best_distance) {
            best = &candidate;
            best_distance = distance;
        }
    }
    if (best && word.size() < 64 && best_distance <= std::max<size_t>(1, best->size() / 3))
        return "; did you mean '" + *best + "'?";
    std::string list;
    for (size_t i = 0; i < candidates.size(); ++i) {
        if (i > 0) list += i + 1 == candidates.size() ? " or " : ", ";
        list += candidates[i];
    }
    return ": expected " + list;
}

template <size_t N>
std::vector<std::string> to_strings(const char* const (&list)[N]) {
    return std::vector<std::string>(std::begin(list), std::end(list));
}

std::string plural(int64_t count, const char* singular, const char* plural_form) {
    return std::to_string(count) + " " + (count == 1 ? singular : plural_form);
}

class Parser {
public:
    Parser(std::string_view text, const std::string& file_name) : lexer_(text, file_name) { desc_.file = file_name; }

    SceneDesc parse() {
        try {
            while (!lexer_.peek().is_end()) parse_top_level_block();
            check_complete();
            if (curve_count_ > 0 && error_count_ == 0)
                warning(first_curve_,
                        std::string(first_curve_.text) + " is a curve, not a surface: raycast draws nothing for it, as the "
                        "course's ray caster does (" + plural(curve_count_, "curve", "curves") + " in this file " +
                        (curve_count_ == 1 ? "is" : "are") + " not drawn)");
        } catch (const Stop&) {
        }
        if (error_count_ > 0) throw InputError(std::move(diagnostics_));
        desc_.warnings = std::move(diagnostics_);
        return std::move(desc_);
    }

private:
    struct Abandon {};  // leave the current block: its error is recorded
    struct Stop {};     // stop parsing altogether

    // ---- diagnostics -------------------------------------------------------------------------

    void report(const Token& at, Severity severity, std::string message) {
        diagnostics_.push_back(make_diagnostic(lexer_, at, severity, std::move(message)));
        if (severity != Severity::Error) return;
        if (++error_count_ >= kMaxReportedErrors) {
            Diagnostic stop;
            stop.location.file = lexer_.file_name();
            stop.message = string_printf("too many errors (%d): stopping here", error_count_);
            diagnostics_.push_back(std::move(stop));
            throw Stop{};
        }
    }
    void error(const Token& at, std::string message) { report(at, Severity::Error, std::move(message)); }
    void warning(const Token& at, std::string message) { report(at, Severity::Warning, std::move(message)); }
    [[noreturn]] void fail(const Token& at, std::string message) {
        error(at, std::move(message));
        throw Abandon{};
    }

    // Skips tokens until the brace depth is back to `depth` and the next token is one that
    // `resumes` accepts, so that one mistake does not produce a cascade of follow-on errors.
    void recover(int depth, const std::function<bool(const Token&)>& resumes) {
        while (!lexer_.peek().is_end()) {
            if (lexer_.depth() == depth && resumes(lexer_.peek())) return;
            if (lexer_.depth() < depth) return;
            lexer_.take();
        }
    }

    // ---- tokens and numbers ------------------------------------------------------------------

    Token expect_open(const Token& block) {
        const Token open = lexer_.take();
        if (!open.is("{"))
            fail(open, "expected '{' after " + quote_token(block.text) + ", got " + describe(open));
        return open;
    }

    std::string describe(const Token& token) const {
        return token.is_end() ? std::string("the end of the file") : quote_token(token.text);
    }

    // A file name after `field`: one token, or a double-quoted string, which may hold spaces.
    std::string read_file_name(std::string_view field) {
        const Token path = lexer_.take();
        if (path.is_end() || path.is("{") || path.is("}"))
            fail(path, "expected a file name for " + quote_token(field) + ", got " + describe(path));
        if (path.text.front() != '"') return std::string(path.text);
        if (path.text.size() < 2 || path.text.back() != '"')
            fail(path, "the file name's quote is not closed: add a '\"' before the end of the line");
        if (path.text.size() == 2) fail(path, "the file name for " + quote_token(field) + " is empty");
        return std::string(path.text.substr(1, path.text.size() - 2));
    }

    [[noreturn]] void fail_unclosed(const Token& at, const Token& block) {
        fail(at, string_printf("unexpected end of file: %s opened at line %d is not closed",
                               quote_token(block.text).c_str(), block.line));
    }

    float read_float(std::string_view field) {
        const Token token = lexer_.take();
        float value = 0;
        const char* first = token.text.data();
        const char* last = first + token.text.size();
        const NumberResult result = parse_float(first, last, value);
        if (token.is_end() || result.status == NumberStatus::Invalid || result.end != last) {
            fail(token, "expected a number for " + quote_token(field) + ", got " + describe(token));
        }
        if (result.status == NumberStatus::OutOfRange)
            fail(token, "number " + quote_token(token.text) + " for " + quote_token(field) +
                            " is out of range (floats reach about 3.4e38)");
        return value;
    }

    Vec3f read_vec3(std::string_view field) {
        Vec3f v;
        v.x = read_float(field);
        v.y = read_float(field);
        v.z = read_float(field);
        return v;
    }

    int64_t read_int(std::string_view field) {
        const Token token = lexer_.take();
        int64_t value = 0;
        const char* first = token.text.data();
        const char* last = first + token.text.size();
        const NumberResult result = parse_int(first, last, value);
        if (token.is_end() || result.status == NumberStatus::Invalid || result.end != last)
            fail(token, "expected a whole number for " + quote_token(field) + ", got " + describe(token));
        if (result.status == NumberStatus::OutOfRange || value > INT32_MAX || value < INT32_MIN)
            fail(token, "number " + quote_token(token.text) + " for " + quote_token(field) + " is out of range");
        return value;
    }

    // Reads `numX N`, which must open a Lights, Materials or Group block.
    int64_t read_count(const char* field) {
        const Token token = lexer_.take();
        if (!token.is(field)) fail(token, string_printf("expected '%s', got ", field) + describe(token));
        const Token value_token = lexer_.peek();
        const int64_t count = read_int(field);
        if (count < 0) fail(value_token, string_printf("%s must not be negative, got %lld", field, (long long)count));
        return count;
    }

    // ---- blocks of named fields, in any order --------------------------------------------------

    struct Field {
        const char* name;
        std::function<void(const Token& name_token)> read;
        bool required = true;
        bool seen = false;
    };

    // Parses `{ field value ... }` after `block` (whose keyword was taken) and reports required
    // fields that are missing at the closing brace, which it returns.
    Token finish_fields(const Token& block, std::vector<Field>& fields) {
        expect_open(block);
        Token close;
        std::vector<Token> first_given(fields.size());  // where each field was first given
        for (;;) {
            const Token token = lexer_.take();
            if (token.is("}")) {
                close = token;
                break;
            }
            if (token.is_end()) fail_unclosed(token, block);
            auto field = std::find_if(fields.begin(), fields.end(), [&](const Field& f) { return token.is(f.name); });
            if (field == fields.end()) {
                std::vector<std::string> names;
                for (const Field& f : fields) names.push_back(f.name);
                error(token, "unknown field " + quote_token(token.text) + " in " + std::string(block.text) +
                                 suggestion(token.text, names));
                // Keep the block (a typo in one field must not lose the whole material or object):
                // skip the field's values, and any block it opens, up to the next known field.
                skip_unknown_field(fields);
                continue;
            }
            if (field->seen) {
                // The course's starter reads fields in a loop, so the last value wins; say so, and
                // where the overridden one was.
                warning(token, quote_token(token.text) + " is given twice in " + std::string(block.text) +
                                   ": the last value is used");
                report(first_given[static_cast<size_t>(field - fields.begin())], Severity::Note,
                       "the first value was given here");
            } else {
                first_given[static_cast<size_t>(field - fields.begin())] = token;
            }
            field->seen = true;
            field->read(token);
        }
        for (const Field& f : fields)
            if (f.required && !f.seen) error(close, std::string(block.text) + " is missing " + quote_token(f.name));
        return close;
    }

    void skip_unknown_field(const std::vector<Field>& fields) {
        const int depth = lexer_.depth();
        while (!lexer_.peek().is_end()) {
            const Token& next = lexer_.peek();
            if (lexer_.depth() == depth) {
                if (next.is("}")) return;
                const bool known = std::any_of(fields.begin(), fields.end(), [&](const Field& f) { return next.is(f.name); });
                if (known) return;
            }
            lexer_.take();
        }
    }

    // ---- top level ----------------------------------------------------------------------------

    void parse_top_level_block() {
        const Token keyword = lexer_.take();
        const int depth = lexer_.depth();
        try {
            if (keyword.is("PerspectiveCamera") || keyword.is("OrthographicCamera")) {
                camera_block_seen_ = true;
                parse_camera(keyword);
            } else if (keyword.is("Background")) {
                parse_background(keyword);
            } else if (keyword.is("Lights")) {
                parse_lights(keyword);
            } else if (keyword.is("Materials")) {
                parse_materials(keyword);
            } else if (keyword.is("Group")) {
                group_block_seen_ = true;
                if (desc_.root) warning(keyword, string_printf("this Group replaces the one at line %d", desc_.root->location.line));
                desc_.root = parse_group(keyword);
            } else if (keyword.is("}")) {
                fail(keyword, "unexpected '}' outside any block");
            } else {
                fail(keyword, "unknown keyword " + quote_token(keyword.text) +
                                  suggestion(keyword.text, to_strings(kTopLevelKeywords)));
            }
        } catch (const Abandon&) {
            recover(depth, [](const Token& t) { return is_one_of(t.text, kTopLevelKeywords); });
        }
    }

    void check_complete() {
        const SourceLocation file_only{lexer_.file_name(), 0, 0};
        // A camera or Group block that had errors is not also reported as missing.
        if (!desc_.camera && !camera_block_seen_)
            diagnostics_.push_back(
                {Severity::Error, file_only, "the scene has no camera: add a PerspectiveCamera block", ""}),
                ++error_count_;
        if (!desc_.root && !group_block_seen_)
            diagnostics_.push_back({Severity::Error, file_only, "the scene has no Group: there is nothing to render", ""}),
                ++error_count_;
    }

    void parse_camera(const Token& keyword) {
        const bool perspective = keyword.is("PerspectiveCamera");
        CameraDesc camera;
        camera.kind = perspective ? CameraDesc::Kind::Perspective : CameraDesc::Kind::Orthographic;
        camera.location = lexer_.location(keyword);
        Token direction_token, up_token, angle_token, size_token, width_token, height_token;
        std::vector<Field> fields = {
            {"center", [&](const Token&) { camera.center = read_vec3("center"); }},
            {"direction",
             [&](const Token& t) {
                 direction_token = t;
                 camera.direction = read_vec3("direction");
             }},
            {"up",
             [&](const Token& t) {
                 up_token = t;
                 camera.up = read_vec3("up");
             }},
        };
        if (perspective) {
            fields.push_back({"angle", [&](const Token&) {
                                  angle_token = lexer_.peek();
                                  camera.angle_degrees = read_float("angle");
                              }});
        } else {
            fields.push_back({"size", [&](const Token&) {
                                  size_token = lexer_.peek();
                                  camera.size = read_float("size");
                              }});
        }
        fields.push_back({"width",
                          [&](const Token&) {
                              width_token = lexer_.peek();
                              camera.width = static_cast<int>(read_int("width"));
                          },
                          false});
        fields.push_back({"height",
                          [&](const Token&) {
                              height_token = lexer_.peek();
                              camera.height = static_cast<int>(read_int("height"));
                          },
                          false});
        const Token close = finish_fields(keyword, fields);
        // Values are checked once all are known.
        if (fields[1].seen && is_zero(camera.direction))
            error(direction_token, "the camera 'direction' must not be the zero vector");
        else if (fields[2].seen && is_zero(camera.up))
            error(up_token, "the camera 'up' must not be the zero vector");
        else if (fields[1].seen && fields[2].seen) {
            const Vec3f d = normalize_any_length(camera.direction), u = normalize_any_length(camera.up);
            if (length(cross(d, u)) < 1e-6f)
                error(up_token, "the camera 'up' is parallel to 'direction': the image would have no up; "
                                "choose an up vector that is not");
        }
        if (perspective && fields[3].seen && !(camera.angle_degrees > 0 && camera.angle_degrees < 180))
            error(angle_token, string_printf("angle must be more than 0 and less than 180 degrees, got %g",
                                             double(camera.angle_degrees)));
        if (!perspective && fields[3].seen && !(camera.size > 0))
            error(size_token, string_printf("size must be positive, got %g", double(camera.size)));
        const bool has_width = fields[4].seen, has_height = fields[5].seen;
        if (has_width != has_height) error(close, has_width ? "the camera has a width but no height" : "the camera has a height but no width");
        bool size_ok = true;
        if (has_width) size_ok &= check_side("width", camera.width, width_token);
        if (has_height) size_ok &= check_side("height", camera.height, height_token);
        if (has_width && has_height && size_ok &&
            int64_t{camera.width} * int64_t{camera.height} > kMaxImagePixels)
            error(width_token, string_printf("a %d x %d image has more pixels than raycast's limit of %lld "
                                             "(8192 x 8192)",
                                             camera.width, camera.height, (long long)kMaxImagePixels));
        if (desc_.camera)
            warning(keyword, string_printf("this camera replaces the one at line %d", desc_.camera->location.line));
        desc_.camera = camera;
    }

    bool check_side(const char* name, int value, const Token& token) {
        if (value < 1) {
            error(token, string_printf("%s must be at least 1, got %d", name, value));
            return false;
        }
        if (value > kMaxImageSide) {
            error(token, string_printf("%s %d is more than raycast's limit of %d", name, value, kMaxImageSide));
            return false;
        }
        return true;
    }

    void parse_background(const Token& keyword) {
        // A second block replaces the first, as a second camera, Lights or Materials block does:
        // what it leaves out is the default again, not the earlier block's.
        if (background_line_ != 0) {
            warning(keyword, string_printf("this Background block replaces the one at line %d", background_line_));
            desc_.background = SceneDesc{}.background;
            desc_.ambient.reset();
        }
        background_line_ = lexer_.location(keyword).line;
        std::vector<Field> fields = {
            {"color", [&](const Token&) { desc_.background = read_vec3("color"); }, false},
            {"ambientLight", [&](const Token&) { desc_.ambient = read_vec3("ambientLight"); }, false},
        };
        finish_fields(keyword, fields);
    }

    void parse_lights(const Token& keyword) {
        expect_open(keyword);
        const int64_t count = read_count("numLights");
        if (desc_.has_lights_block) warning(keyword, "this Lights block replaces the earlier one");
        desc_.has_lights_block = true;
        parse_counted_items(keyword, "numLights", count, "light", desc_.lights, {"DirectionalLight", "PointLight"},
                            [this](const Token& token) { return parse_light(token); });
    }

    // The items of a Lights or Materials block up to its '}', checked against `count`. An item with
    // an error still takes its place (default values), so that the count and the indices of the
    // items after it stay right; parsing resumes at the next of `item_keywords`.
    template <typename Item, typename ParseItem>
    void parse_counted_items(const Token& keyword, const char* count_field, int64_t count, const std::string& noun,
                             std::vector<Item>& items, std::initializer_list<const char*> item_keywords,
                             ParseItem parse_item) {
        items.clear();
        for (;;) {
            const Token token = lexer_.take();
            if (token.is("}")) {
                if (static_cast<int64_t>(items.size()) != count)
                    error(token, string_printf("%s is %lld but ", count_field, (long long)count) +
                                     plural(static_cast<int64_t>(items.size()), (noun + " is").c_str(),
                                            (noun + "s are").c_str()) +
                                     " given");
                return;
            }
            if (token.is_end()) fail_unclosed(token, keyword);
            if (static_cast<int64_t>(items.size()) == count)
                error(token, string_printf("%s is %lld but more %ss follow", count_field, (long long)count, noun.c_str()));
            const int inner_depth = lexer_.depth();
            try {
                items.push_back(parse_item(token));
            } catch (const Abandon&) {
                if (lexer_.peek().is_end()) throw;  // reported once, not again for the enclosing block
                items.push_back(Item{});
                recover(inner_depth, [&item_keywords](const Token& t) {
                    if (t.is("}")) return true;
                    for (const char* k : item_keywords)
                        if (t.is(k)) return true;
                    return false;
                });
            }
        }
    }

    LightDesc parse_light(const Token& keyword) {
        LightDesc light;
        light.location = lexer_.location(keyword);
        if (keyword.is("DirectionalLight")) {
            light.kind = LightDesc::Kind::Directional;
            Token direction_token;
            std::vector<Field> fields = {
                {"direction",
                 [&](const Token& t) {
                     direction_token = t;
                     light.direction = read_vec3("direction");
                 }},
                {"color", [&](const Token&) { light.color = read_vec3("color"); }},
            };
            finish_fields(keyword, fields);
            if (fields[0].seen && is_zero(light.direction))
                error(direction_token, "the light's 'direction' must not be the zero vector");
        } else if (keyword.is("PointLight")) {
            light.kind = LightDesc::Kind::Point;
            Token attenuation_token;
            std::vector<Field> fields = {
                {"position", [&](const Token&) { light.position = read_vec3("position"); }},
                {"color", [&](const Token&) { light.color = read_vec3("color"); }},
                {"attenuation",
                 [&](const Token& t) {
                     attenuation_token = t;
                     light.attenuation = read_vec3("attenuation");
                 },
                 false},
            };
            finish_fields(keyword, fields);
            const Vec3f& a = light.attenuation;
            if (fields[2].seen && (a.x < 0 || a.y < 0 || a.z < 0 || (a.x == 0 && a.y == 0 && a.z == 0)))
                error(attenuation_token, "attenuation needs three numbers that are not negative and not all zero");
        } else {
            fail(keyword, "unknown light " + quote_token(keyword.text) +
                              suggestion(keyword.text, {"DirectionalLight", "PointLight"}));
        }
        return light;
    }

    void parse_materials(const Token& keyword) {
        expect_open(keyword);
        const int64_t count = read_count("numMaterials");
        if (!desc_.materials.empty()) warning(keyword, "this Materials block replaces the earlier one");
        parse_counted_items(keyword, "numMaterials", count, "material", desc_.materials, {"Material", "PhongMaterial"},
                            [this](const Token& token) { return parse_material(token); });
    }

    MaterialDesc parse_material(const Token& keyword) {
        if (!keyword.is("Material") && !keyword.is("PhongMaterial"))
            fail(keyword, "unknown material " + quote_token(keyword.text) +
                              suggestion(keyword.text, {"Material", "PhongMaterial"}));
        MaterialDesc material;
        material.location = lexer_.location(keyword);
        auto read_exponent = [&](const Token& t) {
            const Token value = lexer_.peek();
            material.shininess = read_float(t.text);
            if (*material.shininess < 0)
                error(value, string_printf("%s must not be negative, got %g", std::string(t.text).c_str(),
                                           double(*material.shininess)));
        };
        std::vector<Field> fields = {
            {"diffuseColor", [&](const Token&) { material.diffuse = read_vec3("diffuseColor"); }, false},
            {"specularColor", [&](const Token&) { material.specular = read_vec3("specularColor"); }, false},
            {"shininess", read_exponent, false},
            {"exponent", read_exponent, false},
            {"texture", [&](const Token&) { material.texture = read_file_name("texture"); }, false},
            {"reflectiveColor", [&](const Token&) { material.reflective = read_vec3("reflectiveColor"); }, false},
            {"transparentColor", [&](const Token&) { material.transparent = read_vec3("transparentColor"); }, false},
            {"indexOfRefraction",
             [&](const Token&) {
                 const Token value = lexer_.peek();
                 material.index_of_refraction = read_float("indexOfRefraction");
                 if (!(material.index_of_refraction > 0))
                     error(value, string_printf("indexOfRefraction must be positive, got %g",
                                                double(material.index_of_refraction)));
             },
             false},
        };
        const Token close = finish_fields(keyword, fields);
        if (fields[2].seen && fields[3].seen) error(close, "give 'shininess' or 'exponent', not both");
        return material;
    }

    // ---- objects ------------------------------------------------------------------------------

    struct NestingGuard {
        Parser& parser;
        NestingGuard(Parser& p, const Token& at) : parser(p) {
            if (++parser.nesting_ > kMaxNestingDepth) {
                parser.diagnostics_.push_back(make_diagnostic(
                    parser.lexer_, at, Severity::Error,
                    string_printf("groups and transforms are nested more than %d levels deep", kMaxNestingDepth)));
                ++parser.error_count_;
                throw Stop{};
            }
        }
        ~NestingGuard() { --parser.nesting_; }
    };

    ObjectDesc parse_group(const Token& keyword) {
        NestingGuard guard(*this, keyword);
        ObjectDesc group;
        group.kind = ObjectDesc::Kind::Group;
        group.location = lexer_.location(keyword);
        expect_open(keyword);
        const int inner_depth = lexer_.depth();
        const int64_t count = read_count("numObjects");
        int64_t objects = 0;
        for (;;) {
            const Token token = lexer_.peek();
            if (token.is("}")) {
                lexer_.take();
                if (objects != count)
                    error(token, string_printf("numObjects is %lld but the group has ", (long long)count) +
                                     plural(objects, "object", "objects"));
                return group;
            }
            if (token.is_end()) fail_unclosed(token, keyword);
            try {
                if (token.is("MaterialIndex")) {
                    lexer_.take();
                    parse_material_index();
                    continue;
                }
                if (!is_one_of(token.text, kObjectKeywords)) {
                    lexer_.take();
                    ++objects;  // a misspelt object is still one of the numObjects
                    std::vector<std::string> candidates = to_strings(kObjectKeywords);
                    candidates.push_back("MaterialIndex");
                    fail(token, "unknown object " + quote_token(token.text) + suggestion(token.text, candidates));
                }
                if (objects == count)
                    error(token, string_printf("numObjects is %lld but more objects follow", (long long)count));
                ++objects;
                group.children.push_back(parse_object(lexer_.take()));
            } catch (const Abandon&) {
                recover(inner_depth, [](const Token& t) {
                    return t.is("}") || t.is("MaterialIndex") || is_one_of(t.text, kObjectKeywords);
                });
            }
        }
    }

    void parse_material_index() {
        const Token value = lexer_.peek();
        const int64_t index = read_int("MaterialIndex");
        const int64_t available = static_cast<int64_t>(desc_.materials.size());
        if (index < 0 || index >= available) {
            // The objects that follow are not also reported as having no material.
            current_material_ = kMaterialInError;
            if (available == 0)
                fail(value, string_printf("material index %lld is out of range: no materials are defined before "
                                          "this point (Materials must come before the Group)",
                                          (long long)index));
            fail(value, string_printf("material index %lld is out of range: the scene has ", (long long)index) +
                            plural(available, "material", "materials") +
                            (available == 1 ? std::string(" (index 0)")
                                            : string_printf(" (0 to %lld)", (long long)(available - 1))));
        }
        current_material_ = static_cast<int>(index);
    }

    ObjectDesc parse_object(const Token& keyword) {
        if (keyword.is("Group")) return parse_group(keyword);
        if (keyword.is("Transform")) return parse_transform(keyword);
        ObjectDesc object;
        object.location = lexer_.location(keyword);
        object.material = current_material_;
        if (keyword.is("BezierCurve") || keyword.is("BsplineCurve")) {
            // Curves need no material: a file of curves alone (the course's scene08) has none.
            object.kind = ObjectDesc::Kind::Curve;
            object.curve = parse_curve(keyword, false);
            if (curve_count_++ == 0) first_curve_ = keyword;
            return object;
        }
        if (keyword.is("RevSurface")) {
            object.kind = ObjectDesc::Kind::RevSurface;
            std::vector<Field> fields = {{"profile", [&](const Token&) { object.curve = parse_profile(); }}};
            finish_fields(keyword, fields);
        } else if (keyword.is("Sphere")) {
            object.kind = ObjectDesc::Kind::Sphere;
            Token radius_token;
            std::vector<Field> fields = {
                {"center", [&](const Token&) { object.sphere.center = read_vec3("center"); }},
                {"radius",
                 [&](const Token&) {
                     radius_token = lexer_.peek();
                     object.sphere.radius = read_float("radius");
                 }},
            };
            finish_fields(keyword, fields);
            if (fields[1].seen && !(object.sphere.radius > 0))
                error(radius_token, string_printf("radius must be positive, got %g", double(object.sphere.radius)));
        } else if (keyword.is("Plane")) {
            object.kind = ObjectDesc::Kind::Plane;
            Token normal_token;
            std::vector<Field> fields = {
                {"normal",
                 [&](const Token& t) {
                     normal_token = t;
                     object.plane.normal = read_vec3("normal");
                 }},
                {"offset", [&](const Token&) { object.plane.offset = read_float("offset"); }},
            };
            finish_fields(keyword, fields);
            if (fields[0].seen && is_zero(object.plane.normal))
                error(normal_token, "the plane's 'normal' must not be the zero vector");
        } else if (keyword.is("Triangle")) {
            object.kind = ObjectDesc::Kind::Triangle;
            std::vector<Field> fields = {
                {"vertex0", [&](const Token&) { object.vertices[0] = read_vec3("vertex0"); }},
                {"vertex1", [&](const Token&) { object.vertices[1] = read_vec3("vertex1"); }},
                {"vertex2", [&](const Token&) { object.vertices[2] = read_vec3("vertex2"); }},
            };
            finish_fields(keyword, fields);
            const Vec3f* v = object.vertices;
            if (fields[0].seen && fields[1].seen && fields[2].seen && is_degenerate_triangle(v[0], v[1], v[2]))
                warning(keyword, "degenerate triangle: its vertices are on one line, so it is never seen");
        } else if (keyword.is("TriangleMesh")) {
            object.kind = ObjectDesc::Kind::TriangleMesh;
            std::vector<Field> fields = {
                {"obj_file",
                 [&](const Token&) {
                     object.mesh_path_location = lexer_.location(lexer_.peek());
                     object.mesh_path = read_file_name("obj_file");
                 }},
            };
            finish_fields(keyword, fields);
        }
        if (object.material == kNoMaterial)
            error(keyword, std::string(keyword.text) + " has no material: put 'MaterialIndex i' before it");
        return object;
    }

    // ---- curves ---------------------------------------------------------------------------------

    // `profile BezierCurve { ... }` or `profile BsplineCurve { ... }`, after the word profile.
    Curve parse_profile() {
        const Token type = lexer_.take();
        if (type.is("BezierCurve") || type.is("BsplineCurve")) return parse_curve(type, true);
        if (type.is_end() || type.is("{") || type.is("}"))
            fail(type, "expected the profile curve after 'profile' (BezierCurve or BsplineCurve), got " + describe(type));
        fail(type, "unknown profile " + quote_token(type.text) + suggestion(type.text, {"BezierCurve", "BsplineCurve"}));
    }

    // The course's `BezierCurve { controls [ x y z ] [ x y z ] ... }` (or BsplineCurve): no count,
    // each point in brackets that are words of their own. A RevSurface's profile must lie in the
    // z = 0 plane, as the course's starter insists.
    Curve parse_curve(const Token& keyword, bool is_profile) {
        Curve curve;
        curve.type = keyword.is("BezierCurve") ? CurveType::Bezier : CurveType::Bspline;
        Token first_off_plane;
        int off_plane = 0;
        std::vector<Field> fields = {{"controls", [&](const Token&) {
                                          curve.controls.clear();
                                          off_plane = 0;
                                          while (lexer_.peek().is("[")) {
                                              Token z_token;
                                              const Vec3f point = read_control_point(z_token);
                                              if (is_profile && point.z != 0 && off_plane++ == 0) first_off_plane = z_token;
                                              curve.controls.push_back(point);
                                          }
                                          check_after_control_points();
                                      }}};
        finish_fields(keyword, fields);
        if (!fields[0].seen) return curve;
        if (off_plane > 0)
            error(first_off_plane,
                  "the profile of a RevSurface must lie in the z = 0 plane (it is turned about the y axis), but this "
                  "point has z = " + std::string(first_off_plane.text) +
                      (off_plane > 1 ? string_printf(" (%d points are off the plane)", off_plane) : std::string()));
        const int count = static_cast<int>(curve.controls.size());
        if (curve.type == CurveType::Bspline && count < kBsplineDegree + 1)
            error(keyword, string_printf("a BsplineCurve of degree %d needs at least %d control points, got %d",
                                         kBsplineDegree, kBsplineDegree + 1, count));
        if (curve.type == CurveType::Bezier && (count < 4 || count % 3 != 1))
            error(keyword, string_printf("a BezierCurve needs 3k+1 control points (4, 7, 10, ...), as the course's "
                                         "starter does, got %d",
                                         count));
        else if (curve.type == CurveType::Bezier && count > kMaxBezierControlPoints)
            error(keyword, string_printf("a BezierCurve may have at most %d control points (degree %d), got %d: a "
                                         "BsplineCurve takes any number",
                                         kMaxBezierControlPoints, kMaxBezierControlPoints - 1, count));
        return curve;
    }

    // `[ x y z ]`, the '[' being next. `z_token` is where z was written.
    Vec3f read_control_point(Token& z_token) {
        const Token open = lexer_.take();
        Vec3f point;
        const char* const names[] = {"x", "y", "z"};
        for (int axis = 0; axis < 3; ++axis) {
            const Token value = lexer_.peek();
            if (value.is("]") || value.is("}") || value.is("[") || value.is_end())
                fail(value, string_printf("a control point has three numbers, x y z: expected its %s, got ", names[axis]) +
                                describe(value));
            if (value.text.size() > 1 && value.text.back() == ']')
                fail(value, "write ']' apart from the number before it: " + quote_token(value.text) +
                                " is read as one word");
            if (axis == 2) z_token = value;
            point[axis] = read_float("controls");
        }
        const Token close = lexer_.take();
        if (!close.is("]"))
            fail(close, string_printf("expected ']' to close the control point opened at line %d, column %d, got ",
                                      open.line, open.column) +
                            describe(close));
        return point;
    }

    // What may follow the last control point is the curve's '}' or another field; a number, a stray
    // ']' or a '[' glued to a number means a bracket went missing.
    void check_after_control_points() {
        const Token next = lexer_.peek();
        if (next.is("]")) fail(next, "unexpected ']': no control point is open (is a '[' missing?)");
        if (next.text.size() > 1 && next.text.front() == '[')
            fail(next, "write '[' apart from the number after it: " + quote_token(next.text) + " is read as one word");
        float number = 0;
        const char* first = next.text.data();
        const char* last = first + next.text.size();
        const NumberResult result = parse_float(first, last, number);
        if (!next.is_end() && result.status != NumberStatus::Invalid && result.end == last)
            fail(next, "expected '[' to start a control point, got " + describe(next));
    }

    ObjectDesc parse_transform(const Token& keyword) {
        NestingGuard guard(*this, keyword);
        ObjectDesc transform;
        transform.kind = ObjectDesc::Kind::Transform;
        transform.location = lexer_.location(keyword);
        expect_open(keyword);
        Mat4 m;
        for (;;) {
            const Token item = lexer_.peek();
            if (!is_one_of(item.text, kTransformItems)) break;
            lexer_.take();
            m = compose(m, item);
        }
        transform.world_from_object = m;
        const Token next = lexer_.peek();
        if (next.is("}")) fail(next, "Transform has no object: expected an object before '}'");
        if (next.is_end()) fail_unclosed(next, keyword);
        if (!is_one_of(next.text, kObjectKeywords)) {
            std::vector<std::string> candidates = to_strings(kObjectKeywords);
            for (const char* item : kTransformItems) candidates.push_back(item);
            fail(next, "unknown transform item or object " + quote_token(next.text) + suggestion(next.text, candidates));
        }
        transform.children.push_back(parse_object(lexer_.take()));
        const Token close = lexer_.take();
        if (close.is_end()) fail_unclosed(close, keyword);
        if (!close.is("}"))
            fail(close, "a Transform holds exactly one object: expected '}', got " + describe(close));
        return transform;
    }

    // Applies one transform item. The course composes M <- M·T, so the item listed last acts on
    // the object first; Matrix4f (and MIT's Matrix) compose on the other side, M <- T·M.
    Mat4 compose(const Mat4& m, const Token& item) {
        if (item.is("Scale")) {
            Vec3f s;
            Token zero_factor;  // the caret goes under the first factor that is 0
            for (int axis = 0; axis < 3; ++axis) {
                const Token factor = lexer_.peek();
                s[axis] = read_float("Scale");
                if (s[axis] == 0 && zero_factor.text.empty()) zero_factor = factor;
            }
            if (!zero_factor.text.empty())
                fail(zero_factor, "a Scale factor of 0 squashes the object flat: the transform could not be inverted");
            return m * Mat4::scale(s);
        }
        if (item.is("UniformScale")) {
            const Token value = lexer_.peek();
            const float s = read_float("UniformScale");
            if (s == 0) fail(value, "UniformScale 0 squashes the object to a point: the transform could not be inverted");
            return m * Mat4::scale({s, s, s});
        }
        if (item.is("Translate")) return m * Mat4::translate(read_vec3("Translate"));
        if (item.is("XRotate")) return m * Mat4::rotate_x(read_float("XRotate"));
        if (item.is("YRotate")) return m * Mat4::rotate_y(read_float("YRotate"));
        if (item.is("ZRotate")) return m * Mat4::rotate_z(read_float("ZRotate"));
        if (item.is("Rotate")) {
            expect_open(item);
            const Token axis_token = lexer_.peek();
            const Vec3f axis = read_vec3("Rotate");
            const float degrees = read_float("Rotate");
            const Token close = lexer_.take();
            if (!close.is("}")) fail(close, "expected '}' after 'Rotate { x y z degrees', got " + describe(close));
            // Not dot(axis, axis) == 0: that underflows for axes of 1e-20 and less, which Mat4::rotate
            // normalises in double without trouble.
            if (is_zero(axis)) fail(axis_token, "the 'Rotate' axis must not be the zero vector");
            return m * Mat4::rotate(axis, degrees);
        }
        // Matrix4f lists columns (the course's port onto a column-major class); Matrix lists rows.
        expect_open(item);
        const Token first_value = lexer_.peek();
        float values[16];
        for (float& v : values) v = read_float(item.text);
        const Token close = lexer_.take();
        if (!close.is("}"))
            fail(close, "expected '}' after the 16 numbers of " + quote_token(item.text) + ", got " + describe(close));
        const Mat4 file_matrix = item.is("Matrix4f") ? Mat4::from_columns(values) : Mat4::from_rows(values);
        // Points are moved by the top three rows and the last is taken as 0 0 0 1: a projective
        // row had been dropped one way and used the other (the object's box did not hold what the
        // rays hit, which differed by traversal), and could hide a zero scale.
        const float* last = file_matrix.m[3];
        if (!(last[0] == 0 && last[1] == 0 && last[2] == 0 && last[3] == 1))
            fail(first_value, string_printf("the last row of %s is %g %g %g %g, not 0 0 0 1: raycast's transforms are "
                                            "affine (a projective matrix would bend rays into curves)",
                                            quote_token(item.text).c_str(), double(last[0]), double(last[1]),
                                            double(last[2]), double(last[3])));
        if (determinant(file_matrix) == 0)
            fail(first_value, quote_token(item.text) + " is singular (its determinant is 0): it cannot be inverted");
        return file_matrix * m;
    }

    Lexer lexer_;
    SceneDesc desc_;
    std::vector<Diagnostic> diagnostics_;
    int error_count_ = 0;
    static constexpr int kNoMaterial = -1;       // no MaterialIndex yet
    static constexpr int kMaterialInError = -2;  // the last MaterialIndex was wrong (and reported)
    int current_material_ = kNoMaterial;
    bool camera_block_seen_ = false;
    int background_line_ = 0;  // of the Background block read, 0 before one
    int curve_count_ = 0;  // BezierCurve and BsplineCurve objects, which draw nothing
    Token first_curve_;
    bool group_block_seen_ = false;
    int nesting_ = 0;
};

}  // namespace

SceneDesc parse_scene(std::string_view file_text, const std::string& file_name) {
    std::string converted;
    const std::string_view text = as_unix_text(file_text, converted);
    // A binary file would make only a cascade of unknown keywords: one error says what it is.
    if (const std::optional<size_t> bad = find_non_text_byte(text))
        throw InputError({non_text_diagnostic(text, *bad, file_name)});
    // The parser recurses once per nesting level (up to kMaxNestingDepth), and every level opens
    // a brace: a text with many braces gets a stack that holds that many levels in any build.
    SceneDesc desc;
    const size_t braces = static_cast<size_t>(std::count(text.begin(), text.end(), '{'));
    call_with_stack_for_depth(braces, [&] { desc = Parser(text, file_name).parse(); });
    desc.source_text = std::string(text);
    return desc;
}

}  // namespace raycast
