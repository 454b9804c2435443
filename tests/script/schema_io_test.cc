#include "script/schema_io.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "script/check.h"

namespace hribench::script {
namespace {

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string all(const std::vector<Problem>& problems) {
  std::string s;
  for (const Problem& p : problems) s += p.text() + "\n";
  return s;
}

// docs/scenario-scripts.md: its key reference is the one the code generates, and every yaml
// example in it validates clean.
TEST(SchemaDocsTest, ReferenceMatchesTheCode) {
  const std::string doc = read_file("docs/scenario-scripts.md");
  ASSERT_FALSE(doc.empty());
  EXPECT_NE(doc.find(schema_reference_markdown()), std::string::npos)
      << "regenerate the key reference section from schema_reference_markdown()";
}

TEST(SchemaDocsTest, EveryYamlExampleValidates) {
  const std::string doc = read_file("docs/scenario-scripts.md");
  size_t count = 0;
  std::vector<std::string> roles;
  for (size_t at = doc.find("```yaml\n"); at != std::string::npos; at = doc.find("```yaml\n", at + 1)) {
    const size_t start = at + 8;
    const size_t end = doc.find("```", start);
    ASSERT_NE(end, std::string::npos);
    const std::string block = doc.substr(start, end - start);
    const std::string name = "docs/scenario-scripts.md#example" + std::to_string(++count);
    const std::vector<Problem> problems = check_text(block, name);
    EXPECT_TRUE(problems.empty()) << all(problems);
    std::vector<core::InputError> errors;
    roles.push_back(parse_scenario(block, name, errors).role);
  }
  EXPECT_GE(count, 3U);
  for (const char* role : {"instructor", "collaborator", "intruder"}) {
    EXPECT_NE(std::find(roles.begin(), roles.end(), role), roles.end()) << role;
  }
}

TEST(SchemaIoTest, ReadsTypedValuesWithLocations) {
  std::vector<core::InputError> errors;
  const Scenario s = parse_scenario(
      "hribench: 1\ntask: t\nrole: intruder\ninstruction: go\nhorizon: 12.5\n"
      "scene:\n  objects:\n    cup: {kind: cup, pose: {xy: [0.5, \"U(-0.1, 0.1)\"]}}\n"
      "acts:\n  a:\n    actor: robot\n    goal: grasped(robot, cup)\nsuccess: grasped(robot, cup)\n",
      "s.yaml", errors);
  EXPECT_TRUE(errors.empty());
  EXPECT_EQ(s.horizon, 12.5);
  ASSERT_EQ(s.scene.objects.size(), 1U);
  const ObjectPose& pose = *s.scene.objects[0].value.pose;
  EXPECT_EQ(pose.xy[0].expr, Expr::Number(0.5));
  EXPECT_EQ(pose.xy[1].expr.kind, Expr::Kind::kUniform);
  EXPECT_EQ(pose.xy[1].where.text, "s.yaml:8:39 (scene.objects.cup.pose.xy[1])");
  ASSERT_EQ(s.success.size(), 1U);  // a single predicate is a list of one
  EXPECT_EQ(s.locations.at("acts.a.goal"), "s.yaml:12:11 (acts.a.goal)");
  // The scenario's JSON keeps unresolved values in their source form.
  const core::Json j = to_json(s);
  EXPECT_EQ(j["scene"]["objects"][0]["pose"]["xy"][1], "U(-0.1, 0.1)");
  EXPECT_EQ(j["acts"][0]["name"], "a");
}

TEST(SchemaIoTest, ReportsEveryUnknownAndMissingKey) {
  std::vector<core::InputError> errors;
  parse_scenario("hribench: 1\ntask: t\nrole: intruder\nbogus: 1\n"
                 "scene:\n  objects:\n    cup: {kind: cup, size: 3}\n  extra: 2\n",
                 "s.yaml", errors);
  std::string text;
  for (const core::InputError& e : errors) text += std::string(e.what()) + "\n";
  EXPECT_NE(text.find("s.yaml:1:1: expected a key 'instruction', got none"), std::string::npos) << text;
  EXPECT_NE(text.find("s.yaml:1:1: expected a key 'acts', got none"), std::string::npos);
  EXPECT_NE(text.find("s.yaml:4:1 (bogus): expected a key of script"), std::string::npos);
  EXPECT_NE(text.find("s.yaml:8:3 (scene.extra): expected a key of scene (objects, distractors), got unknown key 'extra'"),
            std::string::npos);
  EXPECT_NE(text.find("s.yaml:7:28 (scene.objects.cup.size): expected a sequence [...], got '3'"), std::string::npos) << text;
  EXPECT_EQ(errors.size(), 6U) << text;  // + success missing
}

TEST(SchemaIoTest, NamesMustBeIdentifiers) {
  std::vector<core::InputError> errors;
  parse_scenario("vars:\n  \"two words\": 1\n", "s.yaml", errors);
  bool found = false;
  for (const core::InputError& e : errors) {
    found = found || std::string(e.what()) ==
                         "s.yaml:2:3 (vars.two words): expected a name of letters, digits and _ (not starting with a digit), got 'two words'";
  }
  EXPECT_TRUE(found);
}

}  // namespace
}  // namespace hribench::script
