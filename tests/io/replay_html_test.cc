// The replay page (io/replay_html.h): the model rebuilt from a log alone; three.js found under
// the data root (or a clear error) and inlined without its comment lines; the page's data pose
// the TCP where the log's X_WT says at every step.

#include "io/replay_html.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include <nlohmann/json.hpp>

#include "core/paths.h"
#include "eval/episode.h"
#include "eval/script_driver.h"
#include "eval/task_episode.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"
#include "support/test_files.h"

namespace hribench::io {
namespace {

namespace fs = std::filesystem;
using ::hribench::testing::error_of;

// A short oracle episode of I1 (3 s: the robot has started to reach).
const eval::EpisodeLog& point_pick_log() {
  static const eval::EpisodeLog log = [] {
    const script::EpisodeSpec spec = script::sample(script::load_scenario("tasks/I1_point_pick.yaml"), 0);
    std::unique_ptr<policy::Policy> oracle = policy::make_policy("oracle");
    eval::RunOptions options;
    options.horizon = 3.0;
    return eval::run_task_episode(spec, *oracle, eval::setup_of(spec, "oracle"), options).log;
  }();
  return log;
}

std::vector<uint8_t> from_base64(const std::string& text) {
  std::vector<uint8_t> out;
  uint32_t bits = 0;
  int count = 0;
  for (const char c : text) {
    const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const char* at = std::strchr(digits, c);
    if (c == '=' || !at) break;
    bits = (bits << 6) | static_cast<uint32_t>(at - digits);
    if ((count += 6) >= 8) {
      count -= 8;
      out.push_back(static_cast<uint8_t>((bits >> count) & 255));
    }
  }
  return out;
}

TEST(ReplayHtml, ModelOfALogIsTheEpisodesAndRefusesAnotherScript) {
  const eval::EpisodeLog& log = point_pick_log();
  const model::Model model = model_of_log(log);
  const script::EpisodeSpec spec = script::sample(script::load_scenario("tasks/I1_point_pick.yaml"), 0);
  EXPECT_EQ(model.mjcf, model::build(eval::scene_spec_from_episode(spec)).mjcf);
  eval::EpisodeLog changed = log;
  changed.spec_hash = "feed";
  EXPECT_EQ(error_of([&] { model_of_log(changed); }),
            "tasks/I1_point_pick.yaml: expected the script the episode ran (seed 0 -> spec hash feed), got spec "
            "hash " + log.spec_hash + ": the script changed since the run");
  changed.task = "no_such_task";
  EXPECT_EQ(error_of([&] { model_of_log(changed); }),
            "the episode's task: expected a task of " + (core::data_root() / "tasks").string() +
                ", got 'no_such_task'");
}

TEST(ReplayHtml, ThreeJsMissingOrInlinedWithoutCommentLines) {
  const fs::path root = ::hribench::testing::temp_dir("replay_html", "root");
  const fs::path build = root / "node_modules" / "three" / "build";
  EXPECT_EQ(error_of([&] { load_three_js(root); }),
            (build / "three.core.js").string() +
                ": expected three.js (the npm package three pinned in package.json), got no such file: run "
                "scripts/install-deps.sh");
  fs::create_directories(build);
  std::ofstream(build / "three.core.js") << "/**\n * A doc comment.\n */\n\tconst a = 1; // kept\n\n\t// a line\n"
                                            "/* short */ const b = 2;\nconst c = `\n\t\t/* glsl */\nx`;\nexport { a };";
  std::ofstream(build / "three.module.js") << "import { a } from './three.core.js';\n";
  const ThreeJs three = load_three_js(root);
  EXPECT_EQ(three.core, "const a = 1; // kept\n const b = 2;\nconst c = `\nx`;\nexport { a };\n");
  EXPECT_EQ(three.module, "import { a } from './three.core.js';\n");
  fs::remove_all(root);
}

TEST(ReplayHtml, PageDataPoseTheTcpWhereTheLogSays) {
  const eval::EpisodeLog& log = point_pick_log();
  const model::Model model = model_of_log(log);
  const std::string html = replay_html(model, log, load_three_js(core::data_root()), {});
  EXPECT_LT(html.size(), 1'600'000u);
  const std::string open = "<script type=\"application/json\" id=\"replay-data\">";
  const size_t from = html.find(open) + open.size();
  const nlohmann::json data = nlohmann::json::parse(html.substr(from, html.find("</script>", from) - from));
  ASSERT_EQ(data["times"].size(), log.steps.size());
  const std::vector<uint8_t> bytes = from_base64(data["poses"].get<std::string>());
  const size_t moving = data["moving"].size();
  ASSERT_EQ(bytes.size(), log.steps.size() * moving * 7 * sizeof(int16_t));
  std::vector<int16_t> poses(bytes.size() / 2);
  std::memcpy(poses.data(), bytes.data(), bytes.size());
  // The TCP's body moves; its pose composed with the TCP offset is X_WT.
  const int tcp_body = data["tcp"]["body"];
  size_t slot = moving;
  for (size_t i = 0; i < moving; ++i) {
    if (data["moving"][i] == tcp_body) slot = i;
  }
  ASSERT_LT(slot, moving);
  const core::Vec3 offset(data["tcp"]["pos"][0], data["tcp"]["pos"][1], data["tcp"]["pos"][2]);
  double worst = 0;
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const int16_t* p = &poses[(k * moving + slot) * 7];
    const core::Vec3 position(p[0] / 1000.0, p[1] / 1000.0, p[2] / 1000.0);
    const Eigen::Quaterniond rotation =
        Eigen::Quaterniond(p[3] / 32767.0, p[4] / 32767.0, p[5] / 32767.0, p[6] / 32767.0).normalized();
    worst = std::max(worst, (position + rotation * offset - log.steps[k].X_WT.translation).norm());
  }
  EXPECT_LT(worst, 1.5e-3);
  // The robot moved in these 3 s, the person is there, every geom has a type the page draws.
  EXPECT_GT((log.steps.back().X_WT.translation - log.steps.front().X_WT.translation).norm(), 0.02);
  int human = 0;
  for (const nlohmann::json& body : data["bodies"]) human += body["category"] == "human" ? 1 : 0;
  EXPECT_GE(human, 15);
}

}  // namespace
}  // namespace hribench::io
