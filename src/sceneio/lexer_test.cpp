// The scene lexer reads tokens the way the course's scanf("%s")/("%f") parser does: any whitespace
// (space, tab, CR, LF, VT, FF) separates, CRLF files read like LF files, a brace is a token of its
// own even when glued to a number or word (`shininess 20}`, `{x`), `-.16` stays one token, and `#`
// starts a comment to the end of the line (raycast's addition). Every token carries a 1-based line
// and byte column, which the diagnostics print; quote_token and make_diagnostic shape messages.
// The expected tokens and positions below were worked out by hand from the input strings.
#include "sceneio/lexer.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace raycast {
namespace {

// Every token's text, in order.
std::vector<std::string> texts(std::string_view source) {
    Lexer lexer(source, "t.txt");
    std::vector<std::string> out;
    for (Token t = lexer.take(); !t.is_end(); t = lexer.take()) out.emplace_back(t.text);
    return out;
}

// Every token as "text@line:column", then the end token as "<end>@line:column".
std::vector<std::string> positioned(std::string_view source) {
    Lexer lexer(source, "t.txt");
    std::vector<std::string> out;
    for (;;) {
        const Token t = lexer.take();
        const std::string text = t.is_end() ? std::string("<end>") : std::string(t.text);
        out.push_back(text + "@" + std::to_string(t.line) + ":" + std::to_string(t.column));
        if (t.is_end()) return out;
    }
}

using Strings = std::vector<std::string>;

TEST(LexerTest, EveryKindOfWhitespaceSeparatesTokens) {
    EXPECT_EQ(texts("a b\tc\r\nd\ne\vf\fg   h"), (Strings{"a", "b", "c", "d", "e", "f", "g", "h"}));
}

TEST(LexerTest, EmptyAndBlankInputHaveNoTokens) {
    EXPECT_TRUE(texts("").empty());
    EXPECT_TRUE(texts(" \t\r\n\n  ").empty());
}

TEST(LexerTest, CrlfLineEndingsCountOneLineEach) {
    // "\r" is whitespace, "\n" starts the next line; columns restart at 1.
    EXPECT_EQ(positioned("Group {\r\n  numObjects 0\r\n}\r\n"),
              (Strings{"Group@1:1", "{@1:7", "numObjects@2:3", "0@2:14", "}@3:1", "<end>@4:1"}));
}

TEST(LexerTest, OldMacCarriageReturnsAloneAreSpacesNotLineBreaks) {
    // Only LF counts lines (the course's fscanf does not care either way).
    EXPECT_EQ(positioned("a\rb"), (Strings{"a@1:1", "b@1:3", "<end>@1:4"}));
}

TEST(LexerTest, TabsCountAsOneColumnEach) {
    EXPECT_EQ(positioned("\t\tTranslate\t5 0 0"),
              (Strings{"Translate@1:3", "5@1:13", "0@1:15", "0@1:17", "<end>@1:18"}));
}

TEST(LexerTest, ClosingBraceGluedToANumberIsSplitOff) {
    // scene01: `shininess 20}`. The course's "%f" stops at the brace, so must we.
    EXPECT_EQ(positioned("shininess 20}"), (Strings{"shininess@1:1", "20@1:11", "}@1:13", "<end>@1:14"}));
}

TEST(LexerTest, BracesGluedToWordsAreSplitOffOnBothSides) {
    EXPECT_EQ(texts("{x"), (Strings{"{", "x"}));
    EXPECT_EQ(texts("Material{diffuseColor 1 0 0}"), (Strings{"Material", "{", "diffuseColor", "1", "0", "0", "}"}));
    EXPECT_EQ(texts("a{b}c"), (Strings{"a", "{", "b", "}", "c"}));
    EXPECT_EQ(texts("}}{{"), (Strings{"}", "}", "{", "{"}));
}

TEST(LexerTest, NumbersStartingWithADotStayOneToken) {
    // scene04: `direction -.16 -.12 -.5`.
    EXPECT_EQ(texts("direction -.16 -.12 -.5"), (Strings{"direction", "-.16", "-.12", "-.5"}));
    EXPECT_EQ(texts("1e-3 +2.5E+2 .5"), (Strings{"1e-3", "+2.5E+2", ".5"}));
}

TEST(LexerTest, OtherPunctuationIsPartOfTheToken) {
    // Only whitespace, braces and '#' end a token: paths and malformed numbers come through whole.
    EXPECT_EQ(texts("obj_file ../mesh/cube.obj 1.2.3 a,b"), (Strings{"obj_file", "../mesh/cube.obj", "1.2.3", "a,b"}));
}

TEST(LexerTest, HashStartsACommentThatRunsToTheEndOfTheLine) {
    EXPECT_EQ(positioned("a # b { c }\nd"), (Strings{"a@1:1", "d@2:1", "<end>@2:2"}));
    // A comment on the last line without a newline, and whole-line comments.
    EXPECT_EQ(texts("# first\n# second\nx # last"), (Strings{"x"}));
    // CRLF after a comment: the \r is skipped with the comment, the line still counts.
    EXPECT_EQ(positioned("# c\r\ny"), (Strings{"y@2:1", "<end>@2:2"}));
}

TEST(LexerTest, ADoubleQuotedStringIsOneTokenWithItsQuotes) {
    // Spaces, braces and '#' inside quotes belong to the token; braces there do not count.
    EXPECT_EQ(positioned("obj_file \"my {model} #1.obj\"}\nx"),
              (Strings{"obj_file@1:1", "\"my {model} #1.obj\"@1:10", "}@1:29", "x@2:1", "<end>@2:2"}));
    // A quote only opens a string at the start of a token.
    EXPECT_EQ(texts("a\"b c\""), (Strings{"a\"b", "c\""}));
}

TEST(LexerTest, AnUnclosedQuoteRunsToTheEndOfItsLine) {
    EXPECT_EQ(positioned("\"my model.obj }\r\n}"), (Strings{"\"my model.obj }@1:1", "}@2:1", "<end>@2:2"}));
    EXPECT_EQ(texts("\""), (Strings{"\""}));
}

TEST(LexerTest, HashGluedToATokenEndsItAndStartsAComment) {
    EXPECT_EQ(texts("radius 1#comment\ncenter"), (Strings{"radius", "1", "center"}));
}

TEST(LexerTest, BracesInsideCommentsDoNotCountTowardsDepth) {
    Lexer lexer("{ # } }\n", "t.txt");
    lexer.take();
    EXPECT_EQ(lexer.depth(), 1);
    EXPECT_TRUE(lexer.take().is_end());
    EXPECT_EQ(lexer.depth(), 1);
}

TEST(LexerTest, DepthFollowsTheBracesTaken) {
    Lexer lexer("A { B { } } }", "t.txt");
    const int expected[] = {0, 1, 1, 2, 1, 0, -1};  // after each of the 7 tokens
    for (int want : expected) {
        lexer.take();
        EXPECT_EQ(lexer.depth(), want);
    }
}

TEST(LexerTest, PeekDoesNotConsume) {
    Lexer lexer("one two", "t.txt");
    EXPECT_EQ(lexer.peek().text, "one");
    EXPECT_EQ(lexer.peek().text, "one");
    EXPECT_EQ(lexer.take().text, "one");
    EXPECT_EQ(lexer.peek().text, "two");
    EXPECT_EQ(lexer.depth(), 0);
}

TEST(LexerTest, PeekingABraceDoesNotChangeTheDepth) {
    Lexer lexer("{", "t.txt");
    EXPECT_TRUE(lexer.peek().is("{"));
    EXPECT_EQ(lexer.depth(), 0);
    lexer.take();
    EXPECT_EQ(lexer.depth(), 1);
}

TEST(LexerTest, TheEndTokenRepeatsAndKnowsWhereTheFileEnds) {
    Lexer lexer("x\n  ", "t.txt");
    EXPECT_EQ(lexer.take().text, "x");
    for (int i = 0; i < 3; ++i) {
        const Token end = lexer.take();
        EXPECT_TRUE(end.is_end());
        EXPECT_EQ(end.line, 2);
        EXPECT_EQ(end.column, 3);  // after the two trailing spaces
    }
}

TEST(LexerTest, TokenIsComparesTheWholeText) {
    Lexer lexer("Spheres", "t.txt");
    EXPECT_FALSE(lexer.peek().is("Sphere"));
    EXPECT_TRUE(lexer.peek().is("Spheres"));
    EXPECT_FALSE(lexer.peek().is_end());
}

TEST(LexerTest, KeywordsAreCaseSensitiveText) {
    // The lexer keeps case as written; "group" is not "Group".
    Lexer lexer("group", "t.txt");
    EXPECT_FALSE(lexer.peek().is("Group"));
}

TEST(LexerTest, LinesAndColumnsAcrossAMultiLineScene) {
    const std::string scene =
        "Materials {\n"
        "    numMaterials 1\n"
        "\tMaterial { diffuseColor 1 0 0 }\n"
        "}";
    EXPECT_EQ(positioned(scene),
              (Strings{"Materials@1:1", "{@1:11", "numMaterials@2:5", "1@2:18", "Material@3:2", "{@3:11",
                       "diffuseColor@3:13", "1@3:26", "0@3:28", "0@3:30", "}@3:32", "}@4:1", "<end>@4:2"}));
}

TEST(LexerTest, LocationNamesTheFileAndPosition) {
    Lexer lexer("\n  word", "dir/scene.txt");
    const Token t = lexer.take();
    const SourceLocation at = lexer.location(t);
    EXPECT_EQ(at.file, "dir/scene.txt");
    EXPECT_EQ(at.line, 2);
    EXPECT_EQ(at.column, 3);
    EXPECT_EQ(lexer.file_name(), "dir/scene.txt");
}

TEST(LexerTest, LineTextDropsTheLineBreakAndCarriageReturn) {
    Lexer lexer("first\r\nsecond\n\nlast", "t.txt");
    EXPECT_EQ(lexer.line_text(1), "first");
    EXPECT_EQ(lexer.line_text(2), "second");
    EXPECT_EQ(lexer.line_text(3), "");
    EXPECT_EQ(lexer.line_text(4), "last");
    EXPECT_EQ(lexer.line_text(5), "");  // past the end
}

TEST(QuoteTokenTest, PutsPlainTextInSingleQuotes) {
    EXPECT_EQ(quote_token("Sphere"), "'Sphere'");
    EXPECT_EQ(quote_token(""), "''");
}

TEST(QuoteTokenTest, EscapesControlBytesAsHex) {
    EXPECT_EQ(quote_token(std::string_view("a\x01z", 3)), "'a\\x01z'");
    EXPECT_EQ(quote_token("\t"), "'\\x09'");
    EXPECT_EQ(quote_token("\x7f"), "'\\x7f'");
    EXPECT_EQ(quote_token(std::string_view("\0", 1)), "'\\x00'");
}

TEST(QuoteTokenTest, KeepsBytesAboveAsciiAsTheyAre) {
    // UTF-8 text (here "é") prints as it is.
    EXPECT_EQ(quote_token("caf\xc3\xa9"), "'caf\xc3\xa9'");
}

TEST(QuoteTokenTest, CutsTokensLongerThanFortyBytes) {
    const std::string forty(40, 'x');
    EXPECT_EQ(quote_token(forty), "'" + forty + "'");
    EXPECT_EQ(quote_token(forty + "y"), "'" + forty + "...'");
    EXPECT_EQ(quote_token(std::string(1000, 'z')), "'" + std::string(40, 'z') + "...'");
}

TEST(MakeDiagnosticTest, CarriesTheLocationAndTheLineForTheCaret) {
    Lexer lexer("Group {\n  Sphree { }\n}", "s.txt");
    lexer.take();
    lexer.take();
    const Token bad = lexer.take();
    const Diagnostic d = make_diagnostic(lexer, bad, Severity::Error, "unknown object 'Sphree'");
    EXPECT_EQ(d.location.file, "s.txt");
    EXPECT_EQ(d.location.line, 2);
    EXPECT_EQ(d.location.column, 3);
    EXPECT_EQ(d.source_line, "  Sphree { }");
    // The display indents the line by two; the line's own two spaces follow.
    EXPECT_EQ(format_diagnostic(d), "s.txt:2:3: error: unknown object 'Sphree'\n    Sphree { }\n    ^\n");
}

TEST(MakeDiagnosticTest, CaretCopiesTabsSoItLinesUp) {
    Lexer lexer("\tx", "s.txt");
    const Diagnostic d = make_diagnostic(lexer, lexer.take(), Severity::Warning, "w");
    EXPECT_EQ(format_diagnostic(d), "s.txt:1:2: warning: w\n  \tx\n  \t^\n");
}

TEST(MakeDiagnosticTest, LeavesOutLinesWithControlBytes) {
    Lexer lexer(std::string_view("a \x01 b", 5), "s.txt");
    const Diagnostic d = make_diagnostic(lexer, lexer.take(), Severity::Error, "m");
    EXPECT_EQ(d.source_line, "");
    EXPECT_EQ(format_diagnostic(d), "s.txt:1:1: error: m\n");
}

TEST(MakeDiagnosticTest, LeavesOutLinesLongerThanThreeHundredBytes) {
    const std::string long_line = "x " + std::string(299, 'y');  // 301 bytes
    Lexer lexer(long_line, "s.txt");
    EXPECT_EQ(make_diagnostic(lexer, lexer.take(), Severity::Error, "m").source_line, "");
    const std::string ok_line = "x " + std::string(298, 'y');  // 300 bytes
    Lexer ok(ok_line, "s.txt");
    EXPECT_EQ(make_diagnostic(ok, ok.take(), Severity::Error, "m").source_line, ok_line);
}

TEST(MakeDiagnosticTest, AtTheEndOfTheFileShowsTheLastLine) {
    Lexer lexer("Group {\n  numObjects 1", "s.txt");
    Token t;
    do t = lexer.take();
    while (!t.is_end());
    const Diagnostic d = make_diagnostic(lexer, t, Severity::Error, "unexpected end of file");
    EXPECT_EQ(d.location.line, 2);
    EXPECT_EQ(d.location.column, 15);
    EXPECT_EQ(format_diagnostic(d),
              "s.txt:2:15: error: unexpected end of file\n    numObjects 1\n                ^\n");
}

}  // namespace
}  // namespace raycast
