#include "io/episode_video.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "eval/episode.h"
#include "eval/script_driver.h"
#include "gen/evaluation.h"
#include "model/model.h"
#include "render/renderer.h"
#include "sim/data.h"
#include "support/logged_run.h"
#include "support/test_files.h"
#include "support/video_probe.h"

namespace hribench::io {
namespace {

namespace fs = std::filesystem;
using testing::error_of;
using testing::temp_dir;

// A 1.5 s noop episode of I1 with its log saved, made once.
const gen::LoggedEpisode& logged() {
  static const gen::LoggedEpisode episode = [] {
    const fs::path run = testing::make_logged_run("episode_video", "I1", "noop", 1, 3, 1.5);
    return gen::load_logged_episode(run, fs::directory_iterator(run / "logs")->path().string());
  }();
  return episode;
}

TEST(EpisodeVideo, HasOneFramePerLogStepAtTheControlRate) {
  const fs::path dir = temp_dir("episode_video", "probe");
  fs::create_directories(dir);
  EpisodeVideoOptions options;
  options.cameras = {"agentview", "wrist"};
  options.panel_width = 160;
  options.panel_height = 120;
  write_episode_video(logged().spec, logged().log, dir / "episode.mp4", options);
  const auto video = testing::probe_video((dir / "episode.mp4").string());
  EXPECT_EQ(video.codec, "h264");
  EXPECT_EQ(video.pix_fmt, "yuv420p");
  EXPECT_EQ(video.width, 320);
  EXPECT_EQ(video.height, 120 + kBandRows * kBandRowHeight);
  EXPECT_EQ(video.frames, static_cast<int64_t>(logged().log.steps.size()));
  EXPECT_EQ(video.frame_rate, "20/1");
  EXPECT_NEAR(video.duration, static_cast<double>(logged().log.steps.size()) * logged().log.control_dt, 1e-6);
}

// A frame taken from the video at a known step is the live render of that step: the camera
// picture a renderer of the panel's size gives of the state the log records.
TEST(EpisodeVideo, AFrameIsTheRenderOfItsStep) {
  const fs::path dir = temp_dir("episode_video", "frame");
  fs::create_directories(dir);
  EpisodeVideoOptions options;
  options.panel_width = 160;
  options.panel_height = 120;
  options.crf = 12;
  write_episode_video(logged().spec, logged().log, dir / "episode.mp4", options);

  const model::Model model = model::build(eval::scene_spec_from_episode(logged().spec));
  sim::Data data = sim::make_data(model);
  render::Renderer renderer(render::Backend::kOsmesa, *model.m(), 160, 120);
  const size_t step = logged().log.steps.size() - 1;
  eval::pose_from_step(model, logged().log, logged().log.steps[step], data);
  render::Image live;
  ASSERT_TRUE(renderer.render(model, data, model.agentview_camera, live));

  const std::string decoded = testing::decode_frame_rgb((dir / "episode.mp4").string(),
                                                        static_cast<int64_t>(step));
  ASSERT_EQ(decoded.size(), static_cast<size_t>(160 * (120 + kBandRows * kBandRowHeight) * 3));
  double error = 0;
  for (size_t i = 0; i < live.rgb.size(); ++i)  // the panel: the first 120 rows
    error += std::abs(static_cast<uint8_t>(decoded[i]) - static_cast<int>(live.rgb[i]));
  EXPECT_LT(error / static_cast<double>(live.rgb.size()), 4.0);
  // A frame of another moment differs from it by more than compression does.
  const std::string first = testing::decode_frame_rgb((dir / "episode.mp4").string(), 0);
  double other = 0;
  for (size_t i = 0; i < live.rgb.size(); ++i)
    other += std::abs(static_cast<uint8_t>(first[i]) - static_cast<int>(live.rgb[i]));
  EXPECT_GT(other, error);
}

TEST(EpisodeVideo, RefusesWhatItCannotShow) {
  const fs::path path = fs::path(temp_dir("episode_video", "errors")) / "episode.mp4";
  EpisodeVideoOptions three;
  three.cameras = {"agentview", "wrist", "agentview"};
  EXPECT_EQ(error_of([&] { write_episode_video(logged().spec, logged().log, path, three); }),
            path.string() + ": cameras: expected one or two cameras, got 3");
  EpisodeVideoOptions unknown;
  unknown.cameras = {"overhead"};
  const std::string message =
      error_of([&] { write_episode_video(logged().spec, logged().log, path, unknown); });
  EXPECT_NE(message.find("video camera: expected one of"), std::string::npos) << message;
  EXPECT_NE(message.find("'overhead'"), std::string::npos) << message;
  script::EpisodeSpec other = logged().spec;
  other.seed += 1;
  EXPECT_NE(error_of([&] { write_episode_video(other, logged().log, path, {}); })
                .find(": expected the log of episode "),
            std::string::npos);
  eval::EpisodeLog empty = logged().log;
  empty.steps.clear();
  EXPECT_EQ(error_of([&] { write_episode_video(logged().spec, empty, path, {}); }),
            path.string() + ": expected a log with steps, got an empty log");
  EXPECT_FALSE(fs::exists(path));
}

// The band's text at a step of a hand-made log: the person's phase, the cue and the response.
TEST(EpisodeVideo, TheBandSaysWhatHappensAtTheStep) {
  eval::EpisodeLog log;
  log.control_dt = 0.05;
  log.events = {{0.2, eval::EventKind::kActStart, eval::Actor::kHuman, "offer.start", ""},
                {0.4, eval::EventKind::kPhase, eval::Actor::kHuman, "offer.hold_stable", ""},
                {0.5, eval::EventKind::kCue, eval::Actor::kHuman, "offer_ready", ""}};
  eval::StepRecord before_response;
  before_response.time = 0.6;
  before_response.separation = 0.2;
  before_response.approach_speed = 0.5;
  eval::StepRecord after_response = before_response;
  after_response.time = 1.0;
  after_response.separation = 0.9;
  after_response.approach_speed = 0;
  after_response.contacts = {{"panda_link5", false, eval::ContactOther::kHuman, "right_hand",
                              human::BodyRegion{}, 12.0}};
  log.steps = {before_response, after_response};
  eval::EpisodeMetrics metrics;
  metrics.cues = {{"offer", 0.5, 0.8, true, 0.3, false}};
  const eval::MetricConstants c;

  const auto early = video_band(log, 0, metrics, c);
  ASSERT_EQ(early.size(), 2u);
  EXPECT_EQ(early[0][0].text, "t 0.60 s");
  EXPECT_EQ(early[0][1].text, "person: offer.hold_stable");
  EXPECT_EQ(early[0][2].text, "cue offer_ready 0.50 s");
  EXPECT_EQ(early[0][3].text, "robot: none yet (+0.1 s)");
  const double s_p = eval::protective_separation(0.5, 0.2, c);
  EXPECT_EQ(early[1][0].text, fmt::format("d 0.20 m   S_p {:.2f} m", s_p));
  EXPECT_EQ(early[1][1].text, "no contact");

  const auto late = video_band(log, 1, metrics, c);
  EXPECT_EQ(late[0][3].text, "robot responded 0.80 s (+0.30)");
  EXPECT_EQ(late[1][1].text, "contact panda_link5 | right_hand 12 N");
  EXPECT_NE(late[1][1].background, early[1][1].background);  // a human contact stands out

  log.steps[0].separation = std::numeric_limits<double>::infinity();
  EXPECT_EQ(video_band(log, 0, metrics, c)[1][0].text, "no person");
}

}  // namespace
}  // namespace hribench::io
