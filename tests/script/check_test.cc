#include "script/check.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "script/runtime.h"
#include "script/sample.h"
#include "script/schema_io.h"

namespace hribench::script {
namespace {

namespace fs = std::filesystem;

std::string all(const std::vector<Problem>& problems) {
  std::string s;
  for (const Problem& p : problems) s += p.text() + "\n";
  return s;
}

std::vector<std::string> files_in(const std::string& dir, const std::string& ext) {
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() == ext) files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

TEST(CheckTest, GoodExamplesAreCleanAndSample) {
  const std::vector<std::string> files = files_in("tests/data/scripts/good", ".yaml");
  ASSERT_GE(files.size(), 3U);
  std::vector<std::string> roles;
  for (const std::string& file : files) {
    const std::vector<Problem> problems = check(file);
    EXPECT_TRUE(problems.empty()) << file << "\n" << all(problems);
    if (!problems.empty()) continue;
    const Scenario scenario = load_scenario(file);
    roles.push_back(scenario.role);
    for (uint64_t seed = 0; seed < 8; ++seed) EXPECT_NO_THROW(sample(scenario, seed)) << file;
  }
  for (const char* role : {"instructor", "collaborator", "intruder"}) {
    EXPECT_NE(std::find(roles.begin(), roles.end(), role), roles.end()) << "no good example for " << role;
  }
}

// True when `text` matches `pattern`, where '*' in the pattern matches any run of characters
// (used for lists that come from the human layer's catalog, which may grow).
bool matches(const std::string& pattern, const std::string& text) {
  const size_t star = pattern.find('*');
  if (star == std::string::npos) return pattern == text;
  if (text.compare(0, star, pattern, 0, star) != 0) return false;
  for (size_t i = star; i <= text.size(); ++i) {
    if (matches(pattern.substr(star + 1), text.substr(i))) return true;
  }
  return false;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::stringstream s(text);
  for (std::string line; std::getline(s, line);) lines.push_back(line);
  return lines;
}

// Every broken script gives exactly the problems listed in its .expected file (all of them,
// each with file:line:col), and never crashes or hangs.
TEST(CheckTest, BadCorpusGivesTheExpectedProblems) {
  const std::vector<std::string> files = files_in("tests/data/scripts/bad", ".yaml");
  ASSERT_GE(files.size(), 30U);
  for (const std::string& file : files) {
    const std::string expected_path = file.substr(0, file.size() - 5) + ".expected";
    std::ifstream in(expected_path);
    ASSERT_TRUE(in) << "missing " << expected_path;
    std::stringstream expected;
    expected << in.rdbuf();
    const std::vector<Problem> problems = check(file);
    EXPECT_FALSE(problems.empty()) << file;
    const std::vector<std::string> want = lines_of(expected.str());
    const std::vector<std::string> got = lines_of(all(problems));
    EXPECT_EQ(got.size(), want.size()) << file << "\n" << all(problems);
    for (size_t i = 0; i < std::min(got.size(), want.size()); ++i) {
      EXPECT_TRUE(matches(want[i], got[i])) << "expected: " << want[i] << "\n     got: " << got[i];
    }
    for (const Problem& p : problems) {
      // "file:LINE:COL" with a line and a column.
      EXPECT_EQ(p.where.rfind(file + ":", 0), 0U) << p.text();
      const std::string rest = p.where.substr(file.size() + 1);
      EXPECT_TRUE(!rest.empty() && std::isdigit(static_cast<unsigned char>(rest[0]))) << p.text();
      EXPECT_NE(rest.find(':'), std::string::npos) << p.text();
    }
  }
}

// Every prefix of a good script (a truncated file) and single-byte corruptions are checked
// without crashing; whatever comes out clean also samples and compiles.
TEST(CheckTest, TruncatedAndCorruptedScriptsNeverCrash) {
  for (const std::string& file : files_in("tests/data/scripts/good", ".yaml")) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    const std::string good = text.str();
    for (size_t cut = 0; cut < good.size(); cut += 23) {
      EXPECT_FALSE(check_text(good.substr(0, cut), "cut.yaml").empty());  // success comes last
    }
    size_t clean = 0;
    for (size_t at = 0; at < good.size(); at += 31) {
      for (const char c : {'\t', '[', ':', '"', '\xff', '9', '$', '('}) {
        std::string bad = good;
        bad[at] = c;
        if (!check_text(bad, "bad.yaml").empty()) continue;
        ++clean;  // e.g. a digit changed: must sample and compile
        std::vector<core::InputError> errors;
        EXPECT_NO_THROW(compile(sample(parse_scenario(bad, "bad.yaml", errors), 1))) << bad;
      }
    }
    EXPECT_GT(clean, 0U) << file;
  }
}

TEST(CheckTest, EveryProblemIsReportedNotOnlyTheFirst) {
  const std::vector<Problem> problems = check("tests/data/scripts/bad/many_problems.yaml");
  EXPECT_GE(problems.size(), 5U) << all(problems);
  // Sorted by position.
  for (size_t i = 1; i < problems.size(); ++i) {
    EXPECT_LE(std::stoi(problems[i - 1].where.substr(problems[i - 1].where.find(':') + 1)),
              std::stoi(problems[i].where.substr(problems[i].where.find(':') + 1)));
  }
}

TEST(CheckTest, MissingFileIsAProblem) {
  const std::vector<Problem> problems = check("tests/data/scripts/no_such_file.yaml");
  ASSERT_EQ(problems.size(), 1U);
  EXPECT_EQ(problems[0].text(), "tests/data/scripts/no_such_file.yaml: cannot open file");
  EXPECT_THROW(load_scenario("tests/data/scripts/bad/cyclic_after.yaml"), core::InputError);
}

// Constraint-graph checks on small inline scripts.
std::string script_with_acts(const std::string& acts) {
  return "hribench: 1\ntask: t\nrole: collaborator\ninstruction: x\nhorizon: 10\n"
         "scene:\n  objects:\n    box: {kind: box}\n    cube: {kind: cube}\n"
         "acts:\n" + acts + "success:\n  - grasped(robot, cube)\n";
}

TEST(CheckTest, ConstraintGraph) {
  const std::string lid =
      "  lid:\n    actor: human\n    motion: {primitive: hold_lid, object: box, handle: box, hinge: box}\n";
  EXPECT_TRUE(check_text(script_with_acts(lid), "t.yaml").empty()) << all(check_text(script_with_acts(lid), "t.yaml"));
  // before + after that contradict each other: a cycle.
  const auto p1 = check_text(script_with_acts(lid + "  take:\n    actor: robot\n    goal: grasped(robot, cube)\n"
                                                    "    after: lid.close\n    before: lid.open\n"), "t.yaml");
  ASSERT_EQ(p1.size(), 1U) << all(p1);
  EXPECT_NE(p1[0].message.find("cycle"), std::string::npos);
  // The lid opens only after the horizon: the robot act waiting for it can never start.
  const auto p2 = check_text(script_with_acts(
      "  lid:\n    actor: human\n    onset: 9.5\n    motion: {primitive: hold_lid, object: box, handle: box, hinge: box}\n"
      "  take:\n    actor: robot\n    goal: grasped(robot, cube)\n    after: lid.hold\n"), "t.yaml");
  ASSERT_EQ(p2.size(), 1U) << all(p2);
  EXPECT_NE(p2[0].message.find("earliest"), std::string::npos) << all(p2);
  // within without after; a contact window whose end precedes its start.
  const auto p3 = check_text(script_with_acts(lid + "  take:\n    actor: robot\n    goal: grasped(robot, cube)\n    within: 1\n") +
                                 "safety:\n  contact_permitted:\n    - {robot: fingers, human: right.hand, from: lid.close, to: lid.open}\n",
                             "t.yaml");
  ASSERT_EQ(p3.size(), 2U) << all(p3);
  EXPECT_NE(all(p3).find("'after' with 'within'"), std::string::npos);
  EXPECT_NE(all(p3).find("lid.open never comes after lid.close"), std::string::npos);
}

// The optional reward section (docs/python.md): weights >= 0, known keys only; sampled into the
// episode, and absent from a spec's JSON (its hash) when the script has none.
TEST(CheckTest, RewardSection) {
  const std::string take = "  take:\n    actor: robot\n    goal: grasped(robot, cube)\n";
  const std::string plain = script_with_acts(take);
  const std::string weighted = plain + "reward:\n  success: 20\n  contact: 0\n";
  EXPECT_TRUE(check_text(weighted, "t.yaml").empty()) << all(check_text(weighted, "t.yaml"));
  std::vector<core::InputError> errors;
  const EpisodeSpec spec = sample(parse_scenario(weighted, "t.yaml", errors), 3);
  ASSERT_TRUE(spec.reward.has_value());
  EXPECT_EQ(spec.reward->success, 20.0);
  EXPECT_EQ(spec.reward->contact, 0.0);
  EXPECT_EQ(spec.reward->progress, 1.0);  // the default
  EXPECT_NE(spec_to_text(spec).find("\"reward\""), std::string::npos);
  EXPECT_EQ(spec_from_text(spec_to_text(spec), "spec").reward, spec.reward);
  const EpisodeSpec without = sample(parse_scenario(plain, "t.yaml", errors), 3);
  EXPECT_FALSE(without.reward.has_value());
  EXPECT_EQ(spec_to_text(without).find("\"reward\""), std::string::npos);

  const auto negative = check_text(plain + "reward:\n  progress: -1\n", "t.yaml");
  ASSERT_EQ(negative.size(), 1U) << all(negative);
  EXPECT_NE(negative[0].text().find("(reward.progress): expected a weight >= 0, got -1"), std::string::npos)
      << all(negative);
  const auto unknown = check_text(plain + "reward:\n  speed: 1\n", "t.yaml");
  ASSERT_EQ(unknown.size(), 1U) << all(unknown);
  EXPECT_NE(unknown[0].text().find("reward.speed"), std::string::npos) << all(unknown);
}

// A variant's acts exist only in its episodes: top-level acts and other variants cannot use them.
TEST(CheckTest, VariantActsAreVisibleOnlyInTheirVariant) {
  const std::string text =
      "hribench: 1\ntask: t\nrole: collaborator\ninstruction: x\n"
      "scene:\n  objects:\n    cube: {kind: cube}\n"
      "acts:\n  take:\n    actor: robot\n    goal: grasped(robot, cube)\n    after: wave.end\n"
      "variants:\n  a:\n    acts:\n      wave:\n        actor: human\n        motion: {primitive: go}\n"
      "  b:\n    acts:\n      wait:\n        actor: robot\n        goal: still(robot)\n        after: wave.start\n"
      "      ok:\n        actor: robot\n        goal: still(robot)\n        after: wait.end\n"
      "success:\n  - grasped(robot, cube)\n";
  const auto problems = check_text(text, "v.yaml");
  ASSERT_EQ(problems.size(), 2U) << all(problems);
  // An act that every variant defines can be named from the top level.
  const std::string both = text.substr(0, text.find("  b:\n")) +
                           "  b:\n    acts:\n      wave:\n        actor: human\n        motion: {primitive: stop}\n"
                           "success:\n  - grasped(robot, cube)\n";
  EXPECT_TRUE(check_text(both, "v.yaml").empty()) << all(check_text(both, "v.yaml"));
  EXPECT_EQ(problems[0].text(), "v.yaml:12:12 (acts.take.after): expected an event ACT.start, ACT.end or ACT.PHASE (acts: take), got 'wave.end'");
  EXPECT_EQ(problems[1].text(), "v.yaml:24:16 (variants.b.acts.wait.after): expected an event ACT.start, ACT.end or ACT.PHASE (acts: take, wait, ok), got 'wave.start'");
}

TEST(CheckTest, PredicatesWithVarsAreCheckedForEveryValue) {
  const std::string text =
      "hribench: 1\ntask: t\nrole: collaborator\ninstruction: x\nvars:\n  target: choice([cube, mug])\n"
      "scene:\n  objects:\n    cube: {kind: cube}\n"
      "acts:\n  take:\n    actor: robot\n    goal: grasped(robot, $target)\n"
      "success:\n  - grasped(robot, cube)\n";
  const auto problems = check_text(text, "v.yaml");
  ASSERT_EQ(problems.size(), 1U) << all(problems);
  EXPECT_EQ(problems[0].text(),
            "v.yaml:13:11 (acts.take.goal): expected a scene object as argument 2 of grasped(robot, OBJECT) "
            "(scene objects: cube), got 'mug' (in 'grasped(robot, mug)')");
}

}  // namespace
}  // namespace hribench::script
