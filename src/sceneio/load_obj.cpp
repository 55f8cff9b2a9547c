#include "sceneio/load_obj.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "base/check.h"
#include "base/error.h"
#include "base/large_allocator.h"
#include "base/limits.h"
#include "base/parallel.h"
#include "base/parse_number.h"
#include "geometry/polygon.h"
#include "sceneio/text_check.h"

namespace raycast {

namespace {

// Mesh arrays are indexed by uint32_t, and kNoNormal takes the last value of the type.
constexpr uint64_t kMaxElements = 0xffffffffu;
// Chunks small enough to balance the threads, large enough that the per-chunk work is noise.
constexpr size_t kMinChunkBytes = size_t{256} << 10;
constexpr size_t kChunksPerThread = 4;
// Files from this size on are read by every thread at once (read_ranges_at_once).
constexpr off_t kMinParallelReadBytes = off_t{1} << 20;
constexpr size_t kMaxTokenShown = 40;

// Byte classes, looked up in one table because the scanning loops test every byte of the file.
// '\r' is a blank, so CRLF files need no special case; a statement ends at '\n' or at a '#' comment.
constexpr uint8_t kBlank = 1;
constexpr uint8_t kStatementEnd = 2;
constexpr uint8_t kSlash = 4;

constexpr std::array<uint8_t, 256> make_byte_classes() {
    std::array<uint8_t, 256> classes{};
    for (unsigned char c : {' ', '\t', '\r', '\v', '\f'}) classes[c] = kBlank;
    classes['\n'] = kStatementEnd;
    classes['#'] = kStatementEnd;
    classes['/'] = kSlash;
    return classes;
}
constexpr std::array<uint8_t, 256> kByteClasses = make_byte_classes();

inline uint8_t byte_class(char c) { return kByteClasses[static_cast<unsigned char>(c)]; }
inline bool is_blank(char c) { return byte_class(c) == kBlank; }
inline bool ends_statement(const char* p, const char* end) { return p == end || byte_class(*p) == kStatementEnd; }
inline bool ends_token(const char* p, const char* end) {
    return p == end || (byte_class(*p) & (kBlank | kStatementEnd)) != 0;
}

inline const char* skip_blanks(const char* p, const char* end) {
    while (p != end && is_blank(*p)) ++p;
    return p;
}

inline const char* skip_token(const char* p, const char* end) {
    while (!ends_token(p, end)) ++p;
    return p;
}

// One past the next '\n' at or after p, or end.
inline const char* next_line(const char* p, const char* end) {
    if (p == end) return end;
    if (*p == '\n') return p + 1;  // where a parsed statement usually stops
#if defined(__SSE2__)
    // Most lines end within a few 16-byte blocks: searched here, without memchr's call and
    // set-up per line (the counting pass skips every vertex line this way).
    const __m128i newline_byte = _mm_set1_epi8('\n');
    for (; end - p >= 16; p += 16) {
        const __m128i block = _mm_loadu_si128(reinterpret_cast<const __m128i*>(p));
        const unsigned found = static_cast<unsigned>(_mm_movemask_epi8(_mm_cmpeq_epi8(block, newline_byte)));
        if (found != 0) return p + __builtin_ctz(found) + 1;
    }
#endif
    const void* newline = std::memchr(p, '\n', static_cast<size_t>(end - p));
    return newline ? static_cast<const char*>(newline) + 1 : end;
}

// A byte order mark (byte_order_mark_length) is no part of the first statement, and files joined
// together (`copy /b a.obj+b.obj`, `cat`) carry one at the start of a line inside: skipped there
// too, or the statement after it would be dropped as unknown and every relative index after it
// would shift. One byte compared per line.
inline const char* skip_byte_order_mark(const char* p, const char* end) {
    return p + byte_order_mark_length(std::string_view(p, static_cast<size_t>(end - p)));
}

enum class Statement { Vertex, Normal, TexCoord, Face, Other };

// Classifies the statement whose keyword starts at p and moves p past the keyword, unless the
// statement is one the loader ignores (o, g, s, usemtl, mtllib, l, p, vp, ...).
inline Statement read_keyword(const char*& p, const char* end) {
    if (p == end) return Statement::Other;
    if (*p == 'v') {
        if (ends_token(p + 1, end)) {
            p += 1;
            return Statement::Vertex;
        }
        if ((p[1] == 'n' || p[1] == 't') && ends_token(p + 2, end)) {
            const Statement statement = p[1] == 'n' ? Statement::Normal : Statement::TexCoord;
            p += 2;
            return statement;
        }
    } else if (*p == 'f' && ends_token(p + 1, end)) {
        p += 1;
        return Statement::Face;
    }
    return Statement::Other;
}

// The token as the user wrote it, for a message: control bytes escaped, at most kMaxTokenShown
// bytes (cut on a UTF-8 character boundary) and "..." when it is longer.
std::string shorten_token(const char* first, const char* last) {
    size_t shown = static_cast<size_t>(last - first);
    const bool cut = shown > kMaxTokenShown;
    if (cut) {
        shown = kMaxTokenShown;
        while (shown > 0 && (static_cast<unsigned char>(first[shown]) & 0xC0) == 0x80) --shown;
    }
    std::string out;
    for (size_t i = 0; i < shown; ++i) {
        const unsigned char c = static_cast<unsigned char>(first[i]);
        if (c < 0x20 || c == 0x7f)
            out += string_printf("\\x%02x", c);
        else
            out += static_cast<char>(c);
    }
    if (cut) out += "...";
    return out;
}

std::string quote_token(const char* first, const char* last) { return "'" + shorten_token(first, last) + "'"; }

// Whether a statement the loader skips is one the OBJ format defines (groups, smoothing,
// materials, free-form geometry, lines, points): skipped in silence. Anything else is a typo
// ('f1', 'V') or not OBJ, skipped with a warning: dropping a line can shift every relative index
// after it.
bool is_known_statement(std::string_view keyword) {
    static constexpr std::string_view kKnown[] = {
        "vp",    "l",    "p",    "o",    "g",    "s",   "mg",    "usemtl",   "mtllib",   "usemap",     "maplib",
        "cstype", "deg", "bmat", "step", "curv", "curv2", "surf", "parm",   "trim",     "hole",       "scrv",
        "sp",    "end",  "con",  "bevel", "c_interp", "d_interp", "lod", "shadow_obj", "trace_obj", "ctech",
        "stech", "call", "csh"};
    for (std::string_view known : kKnown)
        if (keyword == known) return true;
    return false;
}

// Sizes a mesh array that the parser is about to fill, asking for huge pages before the first touch.
// Fresh pages dominated the load time: a 1M-triangle OBJ touches ~14k 4 KiB pages, and a page
// fault costs ~10 us in the virtual machines we run on (2 MiB pages also spare the TLB on bare metal).
template <typename T>
void size_for_writing(std::vector<T>& array, uint64_t size) {
    array.reserve(size);
    advise_huge_pages(array.data(), size * sizeof(T));
    array.resize(size);
}

int saturate_to_int(uint64_t value) { return value > uint64_t{INT_MAX} ? INT_MAX : static_cast<int>(value); }

// A piece of the text that starts at a line start and ends after a '\n' (or at the end of the
// text). Chunks are counted, then parsed, each on its own; the counts give every chunk the global
// line number and element numbers it starts at, so no result depends on where the cuts fall.
struct Chunk {
    const char* begin = nullptr;
    const char* end = nullptr;

    // Filled by count_chunk.
    uint64_t newlines = 0;
    uint64_t vertices = 0;
    uint64_t normals = 0;
    uint64_t texcoords = 0;
    uint64_t triangles = 0;
    uint64_t polygons = 0;  // faces of more than three corners
    bool uses_normals = false;
    const char* first_non_text = nullptr;  // the chunk's first byte that shows a binary file

    // The totals of all chunks before this one.
    uint64_t first_line = 1;
    uint64_t vertex_base = 0;
    uint64_t normal_base = 0;
    uint64_t texcoord_base = 0;
    uint64_t triangle_base = 0;

    std::vector<Diagnostic> errors;
    std::vector<Diagnostic> warnings;  // statements no OBJ reader knows, the first of them
    uint64_t unknown_statements = 0;
    // Faces of more than three corners, written as fans: cut again once every vertex is known
    // (retriangulate_polygons), since a face may name vertices that come later in the file.
    struct Polygon {
        uint64_t first_triangle;
        uint64_t corners;
    };
    std::vector<Polygon> polygon_faces;
};

std::vector<Chunk> split_into_chunks(std::string_view text, int threads, size_t chunk_bytes) {
    size_t target = chunk_bytes;
    if (target == 0) {
        const size_t per_chunk = text.size() / (static_cast<size_t>(threads) * kChunksPerThread);
        target = threads == 1 ? text.size() : std::max(kMinChunkBytes, per_chunk);
    }
    target = std::max<size_t>(target, 1);
    std::vector<Chunk> chunks;
    const char* p = text.data();
    const char* end = p + text.size();
    while (p != end) {
        const char* cut = static_cast<size_t>(end - p) > target ? next_line(p + target - 1, end) : end;
        Chunk chunk;
        chunk.begin = p;
        chunk.end = cut;
        chunks.push_back(std::move(chunk));
        p = cut;
    }
    return chunks;
}

// The first pass: how many elements and triangles the chunk adds, so that the second pass can
// write straight into exactly sized arrays. It must classify lines exactly as ChunkParser does.
// It also finds the first byte that shows the file is binary (sceneio/text_check.h), if any: a
// NUL, or a line that starts like no text; the file is then refused before anything is parsed.
void count_chunk(Chunk& chunk) {
    const char* p = chunk.begin;
    const char* end = chunk.end;
    const char* nul = static_cast<const char*>(std::memchr(p, 0, static_cast<size_t>(end - p)));
    while (p != end) {
        p = skip_blanks(skip_byte_order_mark(p, end), end);
        if (p != end && is_suspect_line_start(static_cast<unsigned char>(*p)) && non_text_problem(p, end)) {
            chunk.first_non_text = nul && nul < p ? nul : p;
            return;
        }
        switch (read_keyword(p, end)) {
        case Statement::Vertex: ++chunk.vertices; break;
        case Statement::Normal: ++chunk.normals; break;
        case Statement::TexCoord: ++chunk.texcoords; break;
        case Statement::Face: {
            uint64_t corners = 0;
            for (;;) {
                p = skip_blanks(p, end);
                if (ends_statement(p, end)) break;
                unsigned slashes = 0;
                for (; p != end; ++p) {
                    const uint8_t c = byte_class(*p);
                    if (c & (kBlank | kStatementEnd)) break;
                    slashes += c / kSlash;
                }
                // Only a corner with a normal has a second slash (a//c, a/b/c).
                if (slashes >= 2) chunk.uses_normals = true;
                ++corners;
            }
            if (corners >= 3) chunk.triangles += corners - 2;
            if (corners > 3) ++chunk.polygons;
            break;
        }
        case Statement::Other: break;
        }
        p = next_line(p, end);
        if (p[-1] == '\n') ++chunk.newlines;
    }
    chunk.first_non_text = nul;
}

// Where the second pass writes; null arrays are not written (the counts exceed the limits, so
// the pass runs for its diagnostics only).
struct MeshOutput {
    Vec3f* positions = nullptr;
    Vec3f* normals = nullptr;
    uint32_t* indices = nullptr;
    uint32_t* normal_indices = nullptr;
    uint64_t vertex_total = 0;
    uint64_t normal_total = 0;
    uint64_t texcoord_total = 0;
};

enum class IndexKind { Vertex, TexCoord, Normal };

// The second pass over one chunk: parses every statement, writes its elements at their global
// positions and records up to kMaxReportedErrors located diagnostics.
class ChunkParser {
public:
    ChunkParser(Chunk& chunk, const MeshOutput& out, const std::string& file_name)
        : chunk_(chunk), out_(out), end_(chunk.end), file_name_(file_name),
          line_(chunk.first_line), vertex_(chunk.vertex_base), normal_(chunk.normal_base),
          texcoord_(chunk.texcoord_base), triangle_(chunk.triangle_base) {}

    void run() {
        if (out_.indices) chunk_.polygon_faces.reserve(chunk_.polygons);
        const char* p = chunk_.begin;
        while (p != end_) {
            p = skip_byte_order_mark(p, end_);
            line_start_ = p;  // columns count from after a byte order mark, which shows as nothing
            p = skip_blanks(p, end_);
            const char* keyword = p;
            switch (read_keyword(p, end_)) {
            case Statement::Vertex: parse_vertex(keyword, p); break;
            case Statement::Normal: parse_normal(keyword, p); break;
            case Statement::TexCoord: parse_texcoord(keyword, p); break;
            case Statement::Face: parse_face(keyword, p); break;
            case Statement::Other:
                if (!ends_statement(p, end_) &&
                    !is_known_statement(std::string_view(p, static_cast<size_t>(skip_token(p, end_) - p))))
                    unknown_statement(p);
                break;
            }
            // Finish the whole line before stopping, so that errors sorted by column within it
            // are complete.
            if (chunk_.errors.size() >= static_cast<size_t>(kMaxReportedErrors)) return;
            p = next_line(p, end_);
            ++line_;
        }
        RAYCAST_CHECK(vertex_ == chunk_.vertex_base + chunk_.vertices);
        RAYCAST_CHECK(triangle_ == chunk_.triangle_base + chunk_.triangles);
    }

private:
    struct Corner {
        uint32_t vertex = 0;
        uint32_t normal = kNoNormal;
    };

    // A diagnostic at `at` on the current line, with the line under it as the scene parser shows
    // its lines: only one a terminal can show (no control bytes, at most 300 bytes). A face of
    // 90,000 corners printed its line, 360 KB, with every error in it.
    Diagnostic diagnostic_at(const char* at, Severity severity, std::string message) const {
        const char* line_end = next_line(line_start_, end_);
        while (line_end != line_start_ && (line_end[-1] == '\n' || line_end[-1] == '\r')) --line_end;
        Diagnostic diagnostic;
        diagnostic.severity = severity;
        const uint64_t column = static_cast<uint64_t>(at - line_start_) + 1;
        diagnostic.location = {file_name_, saturate_to_int(line_), saturate_to_int(column)};
        diagnostic.message = std::move(message);
        const std::string_view line(line_start_, static_cast<size_t>(line_end - line_start_));
        if (is_displayable_source_line(line)) diagnostic.source_line = std::string(line);
        return diagnostic;
    }

    // Out of line and cold: errors are rare, and the hot loops stay small without them.
    [[gnu::noinline, gnu::cold]] void error(const char* at, std::string message) {
        chunk_.errors.push_back(diagnostic_at(at, Severity::Error, std::move(message)));
    }

    // The OBJ specification lets a '\\' at the end of a line continue the statement on the next
    // one; no modelling tool writes it, and the loader does not read it. Said where it shows: a
    // token '\\' last on its line.
    [[gnu::noinline, gnu::cold]] std::string continuation_hint(const char* token, const char* token_end) const {
        if (token_end - token != 1 || *token != '\\' || !ends_statement(skip_blanks(token_end, end_), end_)) return "";
        return ": a '\\' at the end of a line, which OBJ reads as \"the statement goes on below\", is not read "
               "here: join the two lines";
    }

    // Old Microsoft C libraries printed NaN and infinity as "1.#IND", "-1.#QNAN", "1.#INF": the
    // '#' would start a comment, and the statement end at "1." with the value read as 1 or the
    // coordinates after it missing. Checked where a statement's numbers end at a '#' glued to the
    // last of them; true when it was such a number, reported.
    [[gnu::noinline, gnu::cold]] bool is_microsoft_non_number(const char* comment) {
        static constexpr std::string_view kSuffixes[] = {"IND", "INF", "QNAN", "SNAN"};  // then digits: "1.#IND00"
        const char* after = comment + 1;
        const char* token_end = skip_token(after, end_);
        const std::string_view rest(after, static_cast<size_t>(token_end - after));
        const bool microsoft = std::any_of(std::begin(kSuffixes), std::end(kSuffixes), [&](std::string_view suffix) {
            return rest.substr(0, suffix.size()) == suffix &&
                   rest.find_first_not_of("0123456789", suffix.size()) == std::string_view::npos;
        });
        if (!microsoft) return false;
        const char* token = comment;
        while (token != line_start_ && !is_blank(token[-1])) --token;
        error(token, quote_token(token, token_end) +
                         " is not a number: old Microsoft C libraries wrote NaN and infinity as '1.#IND' and '1.#INF' "
                         "(the '#' is not a comment here), and no mesh may hold them");
        return true;
    }

    // A warning for a statement no OBJ reader knows; the first kMaxReportedErrors of a chunk are
    // kept, the rest counted.
    [[gnu::noinline, gnu::cold]] void unknown_statement(const char* keyword) {
        ++chunk_.unknown_statements;
        if (chunk_.warnings.size() >= static_cast<size_t>(kMaxReportedErrors)) return;
        chunk_.warnings.push_back(diagnostic_at(
            keyword, Severity::Warning,
            "unknown statement " + quote_token(keyword, skip_token(keyword, end_)) +
                ": the line is skipped (raycast reads v, vn, vt and f, and passes over the other OBJ statements: o, "
                "g, s, usemtl, ...)"));
    }

    // Reads the numbers up to the end of the statement, keeps the first three in `values` and
    // reports those that are not numbers. Returns how many there were, counting at most 3.
    int read_numbers(const char*& p, float (&values)[3]) {
        int count = 0;
        for (;;) {
            p = skip_blanks(p, end_);
            if (ends_statement(p, end_)) {
                if (p != end_ && *p == '#' && count > 0 && !is_blank(p[-1]) && is_microsoft_non_number(p)) {
                    p = skip_token(p + 1, end_);
                    if (count < 3) ++count;
                    continue;
                }
                return count;
            }
            float value = 0;
            const NumberResult result = parse_float(p, end_, value);
            if (result.status == NumberStatus::Invalid || !ends_token(result.end, end_)) {
                const char* token_end = skip_token(p, end_);
                error(p, quote_token(p, token_end) + " is not a number" + continuation_hint(p, token_end));
                p = token_end;
            } else {
                if (result.status == NumberStatus::OutOfRange)
                    error(p, "number " + quote_token(p, result.end) + " is out of range");
                else if (count < 3)
                    values[count] = value;
                p = result.end;
            }
            if (count < 3) ++count;
        }
    }

    void parse_vertex(const char* keyword, const char*& p) {
        float xyz[3] = {0, 0, 0};
        if (read_numbers(p, xyz) < 3) error(keyword, "a vertex needs 3 coordinates (x y z)");
        if (vertex_ == kMaxElements) error(keyword, "too many vertices for one mesh (the limit is 4294967295)");
        if (out_.positions) out_.positions[vertex_] = Vec3f(xyz[0], xyz[1], xyz[2]);
        ++vertex_;
    }

    void parse_normal(const char* keyword, const char*& p) {
        float xyz[3] = {0, 0, 0};
        if (read_numbers(p, xyz) < 3) error(keyword, "a normal needs 3 coordinates (x y z)");
        if (normal_ == kMaxElements) error(keyword, "too many normals for one mesh (the limit is 4294967295)");
        if (out_.normals) out_.normals[normal_] = Vec3f(xyz[0], xyz[1], xyz[2]);
        ++normal_;
    }

    // Texture coordinates are checked and counted (faces refer to them) but not kept.
    void parse_texcoord(const char* keyword, const char*& p) {
        float uvw[3] = {0, 0, 0};
        if (read_numbers(p, uvw) < 1) error(keyword, "a texture coordinate needs at least 1 number");
        ++texcoord_;
    }

    // Triangulates the polygon as a fan (v0, vi, vi+1), which keeps its winding, while reading it:
    // no corner list, so a face of any size needs no allocation.
    void parse_face(const char* keyword, const char*& p) {
        uint64_t corners = 0;
        Corner first;
        Corner previous;
        for (;;) {
            p = skip_blanks(p, end_);
            if (ends_statement(p, end_)) break;
            const Corner corner = read_corner(p);
            if (corners == 0) first = corner;
            if (corners >= 2) add_triangle(keyword, first, previous, corner);
            previous = corner;
            ++corners;
        }
        if (corners < 3)
            error(keyword, string_printf("a face needs at least 3 vertices, this one has %llu",
                                         static_cast<unsigned long long>(corners)));
        if (corners > 3 && out_.indices)
            chunk_.polygon_faces.push_back({triangle_ - (corners - 2), corners});
    }

    void add_triangle(const char* keyword, Corner a, Corner b, Corner c) {
        if (triangle_ == kMaxElements) error(keyword, "too many triangles for one mesh (the limit is 4294967295)");
        if (out_.indices) {
            uint32_t* indices = out_.indices + 3 * triangle_;
            indices[0] = a.vertex;
            indices[1] = b.vertex;
            indices[2] = c.vertex;
            if (out_.normal_indices) {
                uint32_t* normal_indices = out_.normal_indices + 3 * triangle_;
                normal_indices[0] = a.normal;
                normal_indices[1] = b.normal;
                normal_indices[2] = c.normal;
            }
        }
        ++triangle_;
    }

    // One index of a face corner, as read.
    struct IndexPart {
        const char* first = nullptr;  // null when the corner has no such part
        const char* last = nullptr;
        int64_t value = 0;
        NumberStatus status = NumberStatus::Invalid;
    };

    bool read_index_part(const char*& p, IndexPart& part) {
        const NumberResult result = parse_int(p, end_, part.value);
        if (result.status == NumberStatus::Invalid) return false;
        part.first = p;
        part.last = result.end;
        part.status = result.status;
        p = result.end;
        return true;
    }

    // Reads one face corner: v, v/t, v//n or v/t/n. A malformed corner is reported whole; a
    // well-formed one has each of its indices checked.
    Corner read_corner(const char*& p) {
        const char* token = p;
        IndexPart vertex;
        IndexPart texcoord;
        IndexPart normal;
        bool well_formed = read_index_part(p, vertex);
        if (well_formed && p != end_ && *p == '/') {
            ++p;
            const bool has_texcoord = p != end_ && *p != '/';
            if (has_texcoord) well_formed = read_index_part(p, texcoord);
            if (well_formed && p != end_ && *p == '/') {
                ++p;
                well_formed = read_index_part(p, normal);
            } else if (!has_texcoord) {
                well_formed = false;  // "a/" names neither a texture coordinate nor a normal
            }
        }
        if (!well_formed || !ends_token(p, end_)) {
            const char* token_end = skip_token(token, end_);
            error(token, "malformed face vertex " + quote_token(token, token_end) + continuation_hint(token, token_end));
            p = token_end;
            return Corner{};
        }
        Corner corner;
        corner.vertex = resolve(vertex, IndexKind::Vertex, out_.vertex_total, vertex_);
        if (texcoord.first) resolve(texcoord, IndexKind::TexCoord, out_.texcoord_total, texcoord_);
        if (normal.first) corner.normal = resolve(normal, IndexKind::Normal, out_.normal_total, normal_);
        return corner;
    }

    // Turns a 1-based or negative (relative) index into a 0-based one. Positive indices may
    // refer forward, to any element in the file (`total`); negative ones count back from this
    // line, before which `before` elements are defined.
    uint32_t resolve(const IndexPart& part, IndexKind kind, uint64_t total, uint64_t before) {
        if (part.status == NumberStatus::Ok) {
            if (part.value > 0 && static_cast<uint64_t>(part.value) <= total)
                return static_cast<uint32_t>(part.value - 1);
            if (part.value < 0 && static_cast<uint64_t>(-part.value) <= before)
                return static_cast<uint32_t>(before - static_cast<uint64_t>(-part.value));
            if (part.value == 0) {
                error(part.first, "index 0 is invalid: OBJ indices start at 1");
                return 0;
            }
        }
        report_index_out_of_range(part, kind, total, before);
        return 0;
    }

    [[gnu::noinline, gnu::cold]] void report_index_out_of_range(const IndexPart& part, IndexKind kind, uint64_t total,
                                                                uint64_t before) {
        const char* singular = kind == IndexKind::Vertex   ? "vertex"
                               : kind == IndexKind::Normal ? "normal"
                                                           : "texture coordinate";
        const char* plural = kind == IndexKind::Vertex    ? "vertices"
                             : kind == IndexKind::Normal ? "normals"
                                                         : "texture coordinates";
        // An index too large for parse_int is shown as written; its sign still tells the direction.
        const std::string shown = part.status == NumberStatus::Ok
                                      ? string_printf("%lld", static_cast<long long>(part.value))
                                      : shorten_token(part.first, part.last);
        std::string message = std::string(singular) + " index " + shown + " is out of range: ";
        if (*part.first == '-') {
            message += string_printf("%llu %s %s defined before this line", static_cast<unsigned long long>(before),
                                     before == 1 ? singular : plural, before == 1 ? "is" : "are");
        } else {
            message += string_printf("the file has %llu %s", static_cast<unsigned long long>(total),
                                     total == 1 ? singular : plural);
        }
        error(part.first, std::move(message));
    }

    Chunk& chunk_;
    const MeshOutput& out_;
    const char* end_;
    const std::string& file_name_;
    const char* line_start_ = nullptr;
    uint64_t line_;
    uint64_t vertex_;  // elements defined before the current line, in the whole file
    uint64_t normal_;
    uint64_t texcoord_;
    uint64_t triangle_;
};

// Cuts each face of more than three corners again where its fan was wrong (a concave polygon) or
// slow (a convex one of very many corners, whose slivers all reach its first corner):
// triangulate_polygon on its corners, now that every vertex is known. The face keeps its
// count − 2 triangles, in the same places, so nothing moves.
void retriangulate_polygons(const std::vector<Chunk>& chunks, TriangleMesh& mesh, int threads) {
    parallel_for(chunks.size(), threads, [&](size_t item, int) {
        if (chunks[item].polygon_faces.empty()) return;
        // Room for the corners of a face, grown for the rare faces of very many.
        std::vector<uint32_t> vertex(kMaxEarClippedCorners), normal(kMaxEarClippedCorners),
            triangles(3 * (kMaxEarClippedCorners - 2));
        std::vector<Vec3f> points(kMaxEarClippedCorners);
        for (const Chunk::Polygon& polygon : chunks[item].polygon_faces) {
            const int n = static_cast<int>(polygon.corners);
            if (static_cast<size_t>(n) > points.size()) {
                vertex.resize(static_cast<size_t>(n));
                normal.resize(static_cast<size_t>(n));
                points.resize(static_cast<size_t>(n));
                triangles.resize(3 * static_cast<size_t>(n - 2));
            }
            uint32_t* indices = &mesh.indices[3 * polygon.first_triangle];
            uint32_t* normal_indices = mesh.has_normals() ? &mesh.normal_indices[3 * polygon.first_triangle] : nullptr;
            // The fan (0, k + 1, k + 2) holds corner 0 first in every triangle, then the rest in turn.
            for (int k = 0; k < n; ++k) {
                const size_t at = k == 0 ? 0 : (k == 1 ? 1 : 3 * static_cast<size_t>(k - 2) + 2);
                vertex[k] = indices[at];
                if (normal_indices) normal[k] = normal_indices[at];
                points[k] = mesh.positions[vertex[k]];
            }
            if (n == 4 && quad_fan_tiles(points[0], points[1], points[2], points[3])) continue;
            if (!triangulate_polygon(points.data(), n, triangles.data())) continue;
            for (int i = 0; i < 3 * (n - 2); ++i) {
                indices[i] = vertex[triangles[i]];
                if (normal_indices) normal_indices[i] = normal[triangles[i]];
            }
        }
    });
}

}  // namespace

TriangleMesh parse_obj(std::string_view file_text, const std::string& file_name, const ObjLoadOptions& options) {
    std::string converted;
    const std::string_view text = as_unix_text(file_text, converted);
    const int threads = std::max(1, options.threads);
    std::vector<Chunk> chunks = split_into_chunks(text, threads, options.chunk_bytes);
    const char* text_begin = text.data();
    parallel_for(chunks.size(), threads, [&](size_t item, int) { count_chunk(chunks[item]); });
    for (const Chunk& chunk : chunks)
        if (chunk.first_non_text) {
            const size_t offset = static_cast<size_t>(chunk.first_non_text - text_begin);
            throw InputError({non_text_diagnostic(text, offset, file_name)});
        }

    uint64_t line = 1;
    uint64_t vertices = 0;
    uint64_t normals = 0;
    uint64_t texcoords = 0;
    uint64_t triangles = 0;
    bool uses_normals = false;
    for (Chunk& chunk : chunks) {
        chunk.first_line = line;
        chunk.vertex_base = vertices;
        chunk.normal_base = normals;
        chunk.texcoord_base = texcoords;
        chunk.triangle_base = triangles;
        line += chunk.newlines;
        vertices += chunk.vertices;
        normals += chunk.normals;
        texcoords += chunk.texcoords;
        triangles += chunk.triangles;
        uses_normals |= chunk.uses_normals;
    }

    // Exactly sized once, written in place by every chunk: no growth, no copies, no slack.
    TriangleMesh mesh;
    MeshOutput out;
    out.vertex_total = vertices;
    out.normal_total = normals;
    out.texcoord_total = texcoords;
    const bool fits = vertices <= kMaxElements && normals <= kMaxElements && triangles <= kMaxElements;
    if (fits) {
        size_for_writing(mesh.positions, vertices);
        size_for_writing(mesh.normals, normals);
        size_for_writing(mesh.indices, 3 * triangles);
        if (uses_normals) size_for_writing(mesh.normal_indices, 3 * triangles);
        out.positions = mesh.positions.data();
        out.normals = mesh.normals.data();
        out.indices = mesh.indices.data();
        out.normal_indices = uses_normals ? mesh.normal_indices.data() : nullptr;
    }
    parallel_for(chunks.size(), threads, [&](size_t item, int) {
        ChunkParser(chunks[item], out, file_name).run();
    });

    std::vector<Diagnostic> errors;
    for (Chunk& chunk : chunks) {
        for (Diagnostic& diagnostic : chunk.errors) errors.push_back(std::move(diagnostic));
        if (errors.size() >= static_cast<size_t>(kMaxReportedErrors)) break;
    }
    // Within a line, a count error at the keyword is found after the token errors that follow it.
    std::stable_sort(errors.begin(), errors.end(), [](const Diagnostic& a, const Diagnostic& b) {
        return a.location.line != b.location.line ? a.location.line < b.location.line
                                                  : a.location.column < b.location.column;
    });
    if (errors.size() > static_cast<size_t>(kMaxReportedErrors)) errors.resize(static_cast<size_t>(kMaxReportedErrors));
    RAYCAST_CHECK(fits || !errors.empty());
    if (!errors.empty()) throw InputError(std::move(errors));
    retriangulate_polygons(chunks, mesh, threads);
    if (options.warnings) {
        uint64_t unknown = 0, shown = 0;
        for (Chunk& chunk : chunks) {
            unknown += chunk.unknown_statements;
            for (Diagnostic& warning : chunk.warnings)
                if (shown < static_cast<uint64_t>(kMaxReportedErrors)) {
                    options.warnings->push_back(std::move(warning));
                    ++shown;
                }
        }
        if (unknown > shown) {
            Diagnostic note;
            note.severity = Severity::Note;
            note.location.file = file_name;
            note.message = string_printf("%llu more lines with unknown statements were skipped",
                                         static_cast<unsigned long long>(unknown - shown));
            options.warnings->push_back(std::move(note));
        }
    }
    return mesh;
}

namespace {

// Reads [0, size) of a regular file into `buffer` with every thread at once, each a range of it:
// the kernel's copy and the zeroing of the buffer's fresh pages are most of a large file's read,
// and both go as fast as there are threads to do them. Returns 0 when every range was read, the
// errno of a read that failed, or -1 when a range came back short (the file shrank while read:
// the caller reads it again from the start).
int read_ranges_at_once(int fd, char* buffer, size_t size, int threads) {
    // As many ranges as the parse's chunks (four a thread, none under kMinChunkBytes), so that a
    // huge thread count does not wake a thread for every few bytes.
    const size_t ranges = std::clamp<size_t>(size / kMinChunkBytes, 1, static_cast<size_t>(std::max(1, threads)) * kChunksPerThread);
    const size_t range_bytes = (size + ranges - 1) / ranges;
    std::vector<int> failures(ranges, 0);  // per range, as the whole read's result
    parallel_for(ranges, threads, [&](size_t item, int) {
        size_t offset = std::min(size, item * range_bytes);
        const size_t end = std::min(size, offset + range_bytes);
        while (offset < end) {
            const ssize_t got = ::pread(fd, buffer + offset, end - offset, static_cast<off_t>(offset));
            if (got < 0 && errno == EINTR) continue;
            if (got <= 0) {
                failures[item] = got < 0 ? errno : -1;
                return;
            }
            offset += static_cast<size_t>(got);
        }
    });
    int result = 0;
    for (int failure : failures) {
        if (failure > 0) return failure;  // a failed read outranks a short range
        if (failure < 0) result = failure;
    }
    return result;
}

}  // namespace

TriangleMesh load_obj_file(const std::string& path, const ObjLoadOptions& options) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) throw InputError(path, std::string("cannot open OBJ file: ") + std::strerror(errno));
    struct FileCloser {
        int fd;
        ~FileCloser() { ::close(fd); }
    } closer{fd};
    struct stat info;
    if (::fstat(fd, &info) != 0) throw InputError(path, std::string("cannot open OBJ file: ") + std::strerror(errno));
    if (S_ISDIR(info.st_mode)) throw InputError(path, "cannot open OBJ file: it is a directory");
    if (options.opened) *options.opened = version_of(info);

    // One read into one buffer sized from the file; the +1 finds the end without a second
    // allocation. Pipes and files that grow while read make the buffer grow.
    size_t capacity = S_ISREG(info.st_mode) ? static_cast<size_t>(info.st_size) + 1 : size_t{1} << 16;
    std::unique_ptr<char[]> buffer(new char[capacity]);
    advise_huge_pages(buffer.get(), capacity);
    size_t size = 0;
    // A large file is read by every thread at once (1M triangles, 37 MB: 9 ms on one thread, 5
    // on two; docs/performance.md), then by the loop below from where that ended, which sees a
    // file that grew meanwhile, and the end. A small one is not worth waking the threads for.
    auto cannot_read = [&path](int error) {
        return InputError(path, std::string("cannot read OBJ file: ") + std::strerror(error));
    };
    if (S_ISREG(info.st_mode) && info.st_size >= kMinParallelReadBytes && options.threads > 1) {
        const size_t expected = capacity - 1;
        const int failure = read_ranges_at_once(fd, buffer.get(), expected, options.threads);
        if (failure > 0) throw cannot_read(failure);
        if (failure == 0) size = expected;
        if (::lseek(fd, static_cast<off_t>(size), SEEK_SET) < 0) throw cannot_read(errno);
    }
    for (;;) {
        if (size == capacity) {
            std::unique_ptr<char[]> bigger(new char[2 * capacity]);
            advise_huge_pages(bigger.get(), 2 * capacity);
            std::memcpy(bigger.get(), buffer.get(), size);
            buffer = std::move(bigger);
            capacity *= 2;
        }
        const ssize_t got = ::read(fd, buffer.get() + size, capacity - size);
        if (got < 0) {
            if (errno == EINTR) continue;
            throw cannot_read(errno);
        }
        if (got == 0) break;
        size += static_cast<size_t>(got);
    }
    return parse_obj(std::string_view(buffer.get(), size), path, options);
}

}  // namespace raycast
