#include "core/yaml.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace hribench::core {
namespace {

std::vector<std::string> problems_of(const std::string& text) {
  std::vector<InputError> problems;
  parse_yaml(text, "s.yaml", problems);
  std::vector<std::string> lines;
  for (const InputError& p : problems) lines.push_back(p.what());
  return lines;
}

TEST(YamlTest, CleanTextHasNoProblemsAndKeepsMarks) {
  std::vector<InputError> problems;
  const YamlDocument doc = parse_yaml("a: 1\nb:\n  c: [x, 'y']\n", "s.yaml", problems);
  EXPECT_TRUE(problems.empty());
  EXPECT_EQ(yaml_where(doc.file, doc.root["b"]["c"].Mark(), "b.c"), "s.yaml:3:6 (b.c)");
  EXPECT_FALSE(yaml_quoted(doc.root["b"]["c"][0]));
  EXPECT_TRUE(yaml_quoted(doc.root["b"]["c"][1]));
  EXPECT_EQ(yaml_kind(doc.root["b"]), "a mapping");
  EXPECT_EQ(yaml_kind(doc.root["a"]), "'1'");
}

TEST(YamlTest, DuplicateKeysAreReportedEachTime) {
  const auto p = problems_of("a: 1\nb:\n  c: 1\n  c: 2\na: 3\n");
  ASSERT_EQ(p.size(), 2U);
  EXPECT_EQ(p[0], "s.yaml:4:3 (b.c): expected each key once in a mapping, got 'c' again (first at line 3)");
  EXPECT_EQ(p[1], "s.yaml:5:1 (a): expected each key once in a mapping, got 'a' again (first at line 1)");
}

TEST(YamlTest, TabsInIndentationAreRefused) {
  const auto p = problems_of("a:\n\tb: 1\n\tc: 2\nd: x\ty\n");
  ASSERT_EQ(p.size(), 2U);  // the tab inside "x\ty" is not indentation
  EXPECT_EQ(p[0], "s.yaml:2:1: expected spaces for indentation, got a tab");
  EXPECT_EQ(p[1], "s.yaml:3:1: expected spaces for indentation, got a tab");
}

TEST(YamlTest, NonUtf8BytesAreRefusedWithTheirPosition) {
  const auto p = problems_of("a: ok\nb: caf\xE9\n");
  ASSERT_EQ(p.size(), 1U);
  EXPECT_EQ(p[0], "s.yaml:2:7: expected UTF-8 text, got the byte 0xE9");
  EXPECT_TRUE(problems_of("name: caf\xC3\xA9\n").empty());           // proper UTF-8
  EXPECT_EQ(problems_of("a: \xC0\x80\n").size(), 1U);                 // overlong NUL
  EXPECT_EQ(problems_of("a: \xED\xA0\x80\n").size(), 1U);             // surrogate
  EXPECT_EQ(problems_of(std::string("a: b\0c\n", 7)).size(), 1U);     // control byte
}

TEST(YamlTest, SyntaxErrorsCarryTheLocation) {
  const auto p = problems_of("a: [1, 2\nb: 3\n");
  ASSERT_EQ(p.size(), 1U);
  EXPECT_EQ(p[0].rfind("s.yaml:2:", 0), 0U) << p[0];
  EXPECT_NE(p[0].find("invalid YAML"), std::string::npos);
}

TEST(YamlTest, DeepNestingIsRefusedWithoutCrashing) {
  EXPECT_EQ(problems_of("a: " + std::string(40, '[') + std::string(40, ']') + "\n").size(), 1U);
  EXPECT_EQ(problems_of("a: " + std::string(100000, '[') + std::string(100000, ']') + "\n").size(), 1U);
  EXPECT_TRUE(problems_of("a: " + std::string(20, '[') + std::string(20, ']') + "\n").empty());
}

TEST(YamlTest, AliasBombsStop) {
  std::string text = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 9; ++i) {
    const std::string prev = "*a" + std::to_string(i - 1);
    text += "a" + std::to_string(i) + ": &a" + std::to_string(i) + " [" + prev + ", " + prev +
            ", " + prev + ", " + prev + ", " + prev + ", " + prev + ", " + prev + ", " + prev +
            ", " + prev + ", " + prev + "]\n";
  }
  const auto p = problems_of(text);
  ASSERT_EQ(p.size(), 1U);
  EXPECT_NE(p[0].find("nodes"), std::string::npos);
}

// The 37-byte script of issue 22: a cyclic alias is infinitely deep. The depth is reported once
// and the tree is not handed on (root null), so no reader follows the cycle.
TEST(YamlTest, CyclicAliasIsRefusedAndNotHandedOn) {
  std::vector<InputError> problems;
  const YamlDocument doc = parse_yaml("acts:\n  a: &a\n    motion:\n      x: *a\n", "c.yaml", problems);
  ASSERT_EQ(problems.size(), 1U);
  EXPECT_EQ(problems[0].expected(), "nesting at most 32 deep");
  EXPECT_EQ(problems[0].got(), "deeper nesting");
  EXPECT_EQ(problems[0].where().rfind("c.yaml:2:6 (acts.a.motion.x.motion.x.", 0), 0U) << problems[0].where();
  EXPECT_TRUE(doc.root.IsNull());
}

TEST(YamlTest, ThrowingFormAndMissingFile) {
  EXPECT_THROW(parse_yaml("a: 1\na: 2\n", "t.yaml"), InputError);
  std::vector<InputError> problems;
  load_yaml_file("/nonexistent/x.yaml", problems);
  ASSERT_EQ(problems.size(), 1U);
  EXPECT_EQ(std::string(problems[0].what()), "/nonexistent/x.yaml: cannot open file");
}

}  // namespace
}  // namespace hribench::core
