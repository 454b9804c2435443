#include "io/lerobot.h"

#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>

#include "core/json.h"
#include "io/parquet.h"
#include "support/parquet_readers.h"
#include "support/test_files.h"
#include "support/video_probe.h"

namespace hribench::io {
namespace {

namespace fs = std::filesystem;
using core::Json;
using testing::error_of;
using testing::probe_video;
using testing::read_text;
using testing::temp_dir;

// Frames of 64x48: x264 encodes smaller ones (32x24 tried) differently from one run to the next,
// so their mp4 bytes could not be compared (docs/datasets.md "Reproducible bytes").
constexpr int kWidth = 64;
constexpr int kHeight = 48;

// A synthetic recording (the collector's real rollouts are tested in tests/cli): 8 state and 7
// action dimensions, two cameras, an instruction per task.
EpisodeHeader header(int episode) {
  EpisodeHeader h;
  h.task = episode % 2 == 0 ? "point_pick" : "handover";
  h.task_id = episode % 2 == 0 ? "I1" : "H2";
  h.role = "collaborator";
  h.instruction = episode % 2 == 0 ? "pick the cube the person points at" : "hand the cup over";
  h.spec_hash = "spec" + std::to_string(episode);
  h.seed = 1000 + static_cast<uint64_t>(episode);
  h.variant = episode % 2 == 0 ? "left" : "";
  h.policy = "oracle";
  h.robot = "panda";
  h.fps = 20;
  for (int j = 1; j <= 7; ++j) h.state_names.push_back("joint_pos.panda_joint" + std::to_string(j));
  h.state_names.push_back("gripper.opening");
  for (const char* part : {"dx", "dy", "dz", "drx", "dry", "drz"}) h.action_names.push_back(std::string("ee_delta.") + part);
  h.action_names.push_back("gripper.opening");
  h.action_space = "ee_delta";
  h.cameras = {{"agentview", kWidth, kHeight}, {"wrist", kWidth, kHeight}};
  return h;
}

float state_value(int episode, int64_t frame, size_t d) {
  return 0.25f * static_cast<float>(episode) + 0.01f * static_cast<float>(frame) * static_cast<float>(d + 1);
}

render::Image image(int episode, int64_t frame, int camera) {
  render::Image im;
  im.resize(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      for (int c = 0; c < 3; ++c) {
        im.rgb[(static_cast<size_t>(y) * kWidth + static_cast<size_t>(x)) * 3 + static_cast<size_t>(c)] =
            static_cast<uint8_t>((x * 7 + y * 3 + c * 50 + frame * 11 + episode * 31 + camera * 5) % 256);
      }
    }
  }
  return im;
}

std::string act(int64_t frame) { return frame >= 2 && frame < 4 ? "point" : ""; }

// Streams episode `episode` of `length` frames into a new sink.
std::unique_ptr<EpisodeSink> record(DatasetWriter& writer, int episode, int64_t length) {
  const EpisodeHeader h = header(episode);
  auto sink = writer.begin_episode(h);
  for (int64_t i = 0; i < length; ++i) {
    Frame frame;
    frame.index = i;
    frame.time = static_cast<double>(i) / h.fps;
    for (size_t d = 0; d < h.state_names.size(); ++d) frame.state.push_back(state_value(episode, i, d));
    for (size_t d = 0; d < h.action_names.size(); ++d) frame.action.push_back(-state_value(episode, i, d));
    const render::Image a = image(episode, i, 0);
    const render::Image b = image(episode, i, 1);
    frame.images = {&a, &b};
    frame.human_act = act(i);
    if (i == 2) frame.events = {"cue:point", "act:point begins"};
    frame.reward = i + 1 == length ? 1.0f : 0.0f;
    frame.done = i + 1 == length;
    sink->add(frame);
  }
  return sink;
}

void commit(DatasetWriter& writer, int episode, int64_t length) {
  EpisodeOutcome outcome;
  outcome.success = episode != 2;
  outcome.frames = length;
  if (!outcome.success) outcome.failure_labels = {"timeout"};
  writer.commit(record(writer, episode, length), outcome);
}

// The episodes of the tests: (episode number, length); episode 9 is recorded and discarded.
const std::vector<std::pair<int, int64_t>> kEpisodes = {{0, 5}, {1, 7}, {2, 4}};

void write_dataset(const fs::path& dir, LeRobotVersion version, const LeRobotOptions& options) {
  auto writer = make_lerobot_writer(dir, version, options);
  commit(*writer, kEpisodes[0].first, kEpisodes[0].second);
  writer->discard(record(*writer, 9, 3));
  for (size_t e = 1; e < kEpisodes.size(); ++e) commit(*writer, kEpisodes[e].first, kEpisodes[e].second);
  writer->finish();
}

std::vector<Json> jsonl(const fs::path& path) {
  const std::string text = read_text(path);
  std::vector<Json> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    EXPECT_FALSE(line.empty()) << path << " has a blank line";
    lines.push_back(Json::parse(line));
  }
  EXPECT_TRUE(!text.empty() && text.back() == '\n') << path;
  return lines;
}

std::vector<double> flat(const Json& value) {
  std::vector<double> out;
  if (value.is_array()) {
    for (const Json& v : value) {
      const std::vector<double> inner = flat(v);
      out.insert(out.end(), inner.begin(), inner.end());
    }
  } else {
    out.push_back(value.is_boolean() ? (value.get<bool>() ? 1.0 : 0.0) : value.get<double>());
  }
  return out;
}

using Stats = std::array<std::vector<double>, 6>;

// numpy.quantile(values, q) (linear interpolation).
double numpy_quantile(std::vector<double> values, double q) {
  std::sort(values.begin(), values.end());
  const double position = q * static_cast<double>(values.size() - 1);
  const size_t below = static_cast<size_t>(position);
  const double fraction = position - static_cast<double>(below);
  return below + 1 < values.size() ? values[below] + fraction * (values[below + 1] - values[below]) : values[below];
}

// Stats recomputed here from values the real readers read: {min, max, mean, std, q01, q99} per
// dimension.
Stats recompute(const std::vector<std::vector<double>>& rows) {
  const size_t dims = rows.front().size();
  Stats s;
  for (size_t d = 0; d < dims; ++d) {
    double lo = rows[0][d], hi = rows[0][d], sum = 0;
    for (const auto& r : rows) {
      lo = std::min(lo, r[d]);
      hi = std::max(hi, r[d]);
      sum += r[d];
    }
    const double mean = sum / static_cast<double>(rows.size());
    double var = 0;
    for (const auto& r : rows) var += (r[d] - mean) * (r[d] - mean);
    s[0].push_back(lo);
    s[1].push_back(hi);
    s[2].push_back(mean);
    s[3].push_back(std::sqrt(var / static_cast<double>(rows.size())));
    std::vector<double> column;
    for (const auto& r : rows) column.push_back(r[d]);
    s[4].push_back(numpy_quantile(column, 0.01));
    s[5].push_back(numpy_quantile(column, 0.99));
  }
  return s;
}

void expect_stats(const Json& stats, const Stats& expected, int64_t count, const std::string& what) {
  SCOPED_TRACE(what);
  const char* names[] = {"min", "max", "mean", "std", "q01", "q99"};
  for (size_t s = 0; s < 6; ++s) {
    const std::vector<double> got = flat(stats.at(names[s]));
    ASSERT_EQ(got.size(), expected[s].size()) << names[s];
    for (size_t d = 0; d < got.size(); ++d) EXPECT_NEAR(got[d], expected[s][d], 1e-6) << names[s] << d;
  }
  EXPECT_EQ(stats.at("count"), Json::array({count}));
}

// Per-channel stats of a camera's frames over the given episodes, scaled to [0, 1].
Stats image_stats(const std::vector<std::pair<int, int64_t>>& episodes,
                                               int camera) {
  std::vector<std::vector<double>> pixels;
  for (const auto& [episode, length] : episodes) {
    for (int64_t i = 0; i < length; ++i) {
      const render::Image im = image(episode, i, camera);
      for (size_t p = 0; p < im.rgb.size(); p += 3) {
        pixels.push_back({im.rgb[p] / 255.0, im.rgb[p + 1] / 255.0, im.rgb[p + 2] / 255.0});
      }
    }
  }
  return recompute(pixels);
}

// Checks what both versions share: the rows the real readers read against info.json and the
// recorded frames, every mp4 with ffprobe, stats, the modality file. `data_files` are the
// dataset's parquet files of frames, `rows` maps an episode index to its rows in them.
struct Checked {
  Json info;
  Json tasks;  // task_index -> text
};

void check_rows_and_columns(const Json& info, const Json& read_file, const Json& tasks,
                            std::map<int64_t, std::vector<Json>>& rows_by_episode) {
  const Json& features = info.at("features");
  for (const char* reader : {"hyparquet", "duckdb"}) {
    SCOPED_TRACE(reader);
    for (const Json& row : read_file.at(reader).at("rows")) {
      size_t columns = 0;
      for (const auto& [key, feature] : features.items()) {
        if (feature.at("dtype") == "video") continue;
        ++columns;
        ASSERT_TRUE(row.contains(key)) << key;
        const int64_t size = feature.at("shape").at(0).get<int64_t>();
        if (size == 1) {
          ASSERT_FALSE(row.at(key).is_array()) << key << ": a shape-(1,) feature is a scalar column";
        } else {
          ASSERT_EQ(row.at(key).size(), static_cast<size_t>(size)) << key;
        }
      }
      EXPECT_EQ(row.size(), columns) << "every column is a feature of info.json";
      const double expected_time = static_cast<float>(row.at("frame_index").get<double>() / 20.0);
      EXPECT_EQ(row.at("timestamp").get<double>(), expected_time);
      EXPECT_NEAR(row.at("timestamp").get<double>(), row.at("frame_index").get<double>() / 20.0, 1e-6);
      if (std::string(reader) == "hyparquet") rows_by_episode[row.at("episode_index")].push_back(row);
    }
  }
  if (!read_file.at("duckdb").at("rows").empty()) {
    const Json& types = read_file.at("duckdb").at("types");
    for (const auto& [key, feature] : features.items()) {
      if (feature.at("dtype") == "video") continue;
      const std::string dtype = feature.at("dtype");
      const bool list = feature.at("shape").at(0) != 1;
      const std::string scalar = dtype == "float32" ? "FLOAT" : dtype == "int64" ? "BIGINT" : "BOOLEAN";
      EXPECT_EQ(types.at(key), scalar + (list ? "[]" : "")) << key;
    }
  }
  (void)tasks;
}

// The rows of each episode against what was recorded; returns the per-episode first index.
void check_episode_rows(const std::map<int64_t, std::vector<Json>>& rows_by_episode,
                        const std::vector<std::string>& tasks) {
  int64_t index = 0;
  ASSERT_EQ(rows_by_episode.size(), kEpisodes.size());
  for (const auto& [episode_index, rows] : rows_by_episode) {
    const auto [episode, length] = kEpisodes[static_cast<size_t>(episode_index)];
    ASSERT_EQ(static_cast<int64_t>(rows.size()), length);
    for (int64_t i = 0; i < length; ++i) {
      const Json& row = rows[static_cast<size_t>(i)];
      EXPECT_EQ(row.at("frame_index"), i);
      EXPECT_EQ(row.at("index"), index++) << "index is the global row number";
      EXPECT_EQ(tasks.at(row.at("task_index").get<size_t>()), header(episode).instruction);
      EXPECT_EQ(tasks.at(row.at("annotation.human.act").get<size_t>()), act(i).empty() ? "none" : act(i));
      EXPECT_EQ(tasks.at(row.at("annotation.human.events").get<size_t>()),
                i == 2 ? "cue:point; act:point begins" : "none");
      for (size_t d = 0; d < 8; ++d) {
        EXPECT_EQ(row.at("observation.state")[d].get<double>(), static_cast<double>(state_value(episode, i, d)));
      }
      EXPECT_EQ(row.at("action")[6].get<double>(), static_cast<double>(-state_value(episode, i, 6)));
      EXPECT_EQ(row.at("next.done"), i + 1 == length);
    }
  }
}

std::vector<std::vector<double>> column_rows(const std::vector<Json>& rows, const std::string& key) {
  std::vector<std::vector<double>> out;
  for (const Json& row : rows) out.push_back(flat(row.at(key)));
  return out;
}

void check_modality(const fs::path& dir) {
  const Json modality = core::read_json_file((dir / "meta/modality.json").string());
  for (const auto& [group, size] : {std::pair<std::string, int>{"state", 8}, {"action", 7}}) {
    std::vector<std::pair<int, int>> slices;
    for (const auto& [key, slice] : modality.at(group).items()) slices.emplace_back(slice.at("start"), slice.at("end"));
    std::sort(slices.begin(), slices.end());
    int next = 0;
    for (const auto& [start, end] : slices) {
      EXPECT_EQ(start, next) << group << " slices leave no gap and do not overlap";
      EXPECT_GT(end, start);
      next = end;
    }
    EXPECT_EQ(next, size) << group << " slices cover the vector";
  }
  EXPECT_EQ(modality.at("state").at("joint_pos"), Json({{"start", 0}, {"end", 7}}));
  EXPECT_EQ(modality.at("state").at("gripper"), Json({{"start", 7}, {"end", 8}}));
  EXPECT_EQ(modality.at("action").at("ee_delta"), Json({{"start", 0}, {"end", 6}}));
  EXPECT_EQ(modality.at("video").at("wrist").at("original_key"), "observation.images.wrist");
  EXPECT_EQ(modality.at("annotation").at("human.task_description").at("original_key"), "task_index");
  EXPECT_EQ(modality.at("annotation").at("human.act").at("original_key"), "annotation.human.act");
}

void check_info(const Json& info, const char* version) {
  EXPECT_EQ(info.at("codebase_version"), version);
  EXPECT_EQ(info.at("robot_type"), "panda");
  EXPECT_TRUE(info.at("fps").is_number_integer());
  EXPECT_EQ(info.at("fps"), 20);
  EXPECT_EQ(info.at("total_episodes"), 3);
  EXPECT_EQ(info.at("total_frames"), 16);
  EXPECT_EQ(info.at("splits"), Json({{"train", "0:3"}}));
  const Json& video = info.at("features").at("observation.images.agentview");
  EXPECT_EQ(video.at("dtype"), "video");
  EXPECT_EQ(video.at("shape"), Json({kHeight, kWidth, 3}));
  EXPECT_EQ(video.at("names"), Json({"height", "width", "channels"}));
  EXPECT_EQ(video.at("info").at("video.codec"), "h264");
  EXPECT_EQ(video.at("info").at("video.pix_fmt"), "yuv420p");
  EXPECT_EQ(video.at("info").at("video.fps"), 20);
  EXPECT_EQ(info.at("features").at("observation.state").at("shape"), Json({8}));
  EXPECT_EQ(info.at("features").at("observation.state").at("names").at(7), "gripper.opening");
  EXPECT_EQ(info.at("features").at("timestamp").at("dtype"), "float32");
  EXPECT_EQ(info.at("features").at("index").at("dtype"), "int64");
}

void check_dataset_stats(const fs::path& dir, const std::map<int64_t, std::vector<Json>>& rows_by_episode) {
  const Json stats = core::read_json_file((dir / "meta/stats.json").string());
  std::vector<Json> all;
  for (const auto& [e, rows] : rows_by_episode) all.insert(all.end(), rows.begin(), rows.end());
  // Over all rows, but the quantiles: the count-weighted mean of the episodes' (docs/datasets.md).
  const auto dataset = [&](Stats over_all, const std::function<Stats(size_t)>& of_episode) {
    for (size_t q = 4; q < 6; ++q) {
      for (size_t d = 0; d < over_all[q].size(); ++d) {
        over_all[q][d] = 0;
        for (size_t e = 0; e < kEpisodes.size(); ++e) {
          over_all[q][d] += of_episode(e)[q][d] * static_cast<double>(kEpisodes[e].second) / 16.0;
        }
      }
    }
    return over_all;
  };
  for (const char* key : {"observation.state", "index"}) {
    expect_stats(stats.at(key), dataset(recompute(column_rows(all, key)), [&](size_t e) {
                   return recompute(column_rows(rows_by_episode.at(static_cast<int64_t>(e)), key));
                 }), 16, std::string("stats.json ") + key);
  }
  expect_stats(stats.at("observation.images.wrist"),
               dataset(image_stats(kEpisodes, 1), [&](size_t e) { return image_stats({kEpisodes[e]}, 1); }), 16,
               "stats.json wrist");
  EXPECT_EQ(stats.at("observation.images.wrist").at("mean").size(), 3u);
  EXPECT_EQ(stats.at("observation.images.wrist").at("mean")[0], Json::array({Json::array({stats.at("observation.images.wrist").at("mean")[0][0][0]})}));
}

TEST(LeRobot, V21DatasetReadsBackWithTheRealReadersFfprobeAndRecomputedStats) {
  const fs::path dir = temp_dir("lerobot", "v21");
  write_dataset(dir, LeRobotVersion::kV21, {});
  EXPECT_FALSE(fs::exists(dir / ".staging"));
  const Json info = core::read_json_file((dir / "meta/info.json").string());
  check_info(info, "v2.1");
  EXPECT_EQ(info.at("total_videos"), 6);
  EXPECT_EQ(info.at("total_chunks"), 1);
  EXPECT_EQ(info.at("data_path"), "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet");

  std::vector<std::string> tasks;
  for (const Json& line : jsonl(dir / "meta/tasks.jsonl")) {
    EXPECT_EQ(line.at("task_index"), tasks.size());
    tasks.push_back(line.at("task"));
  }
  EXPECT_EQ(info.at("total_tasks"), tasks.size());
  const std::vector<Json> episodes = jsonl(dir / "meta/episodes.jsonl");
  ASSERT_EQ(episodes.size(), 3u);
  EXPECT_EQ(episodes[1], Json::parse(R"({"episode_index":1,"length":7,"tasks":["hand the cup over"],
      "hribench":{"task":"handover","task_id":"H2","role":"collaborator","spec_hash":"spec1","seed":1001,
      "variant":"","policy":"oracle","action_space":"ee_delta","success":true,"status":"ok","failure_labels":[]}})"));
  EXPECT_EQ(episodes[2].at("hribench").at("failure_labels"), Json({"timeout"}));

  std::vector<std::string> files;
  for (size_t e = 0; e < 3; ++e) files.push_back((dir / fmt::format("data/chunk-000/episode_{:06d}.parquet", e)).string());
  const Json read = testing::read_with_real_readers(files);
  ASSERT_FALSE(read.is_null());
  std::map<int64_t, std::vector<Json>> rows_by_episode;
  for (const std::string& file : files) check_rows_and_columns(info, read.at(file), tasks, rows_by_episode);
  check_episode_rows(rows_by_episode, tasks);

  // Per-episode stats, recomputed from the rows hyparquet read and from the recorded images.
  const std::vector<Json> stats = jsonl(dir / "meta/episodes_stats.jsonl");
  ASSERT_EQ(stats.size(), 3u);
  for (size_t e = 0; e < 3; ++e) {
    const auto& rows = rows_by_episode.at(static_cast<int64_t>(e));
    const int64_t n = kEpisodes[e].second;
    EXPECT_EQ(stats[e].at("episode_index"), e);
    for (const char* key : {"observation.state", "action", "timestamp", "frame_index", "index", "next.reward", "next.done"}) {
      expect_stats(stats[e].at("stats").at(key), recompute(column_rows(rows, key)), n, key);
    }
    const Json& image = stats[e].at("stats").at("observation.images.agentview");
    EXPECT_EQ(image.at("mean").size(), 3u);
    EXPECT_EQ(image.at("mean")[0].size(), 1u);
    EXPECT_EQ(image.at("mean")[0][0].size(), 1u) << "image stats have shape (3, 1, 1)";
    expect_stats(image, image_stats({kEpisodes[e]}, 0), n, "agentview");
  }
  check_dataset_stats(dir, rows_by_episode);
  check_modality(dir);

  for (size_t e = 0; e < 3; ++e) {
    for (const char* camera : {"agentview", "wrist"}) {
      const auto video = probe_video(
          (dir / fmt::format("videos/chunk-000/observation.images.{}/episode_{:06d}.mp4", camera, e)).string());
      EXPECT_EQ(video.codec, "h264");
      EXPECT_EQ(video.pix_fmt, "yuv420p");
      EXPECT_EQ(video.width, kWidth);
      EXPECT_EQ(video.height, kHeight);
      EXPECT_EQ(video.frames, kEpisodes[e].second) << "one frame per row";
      EXPECT_EQ(video.frame_rate, "20/1");
    }
  }
  // Nothing of the discarded episode remains.
  size_t files_on_disk = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) files_on_disk += entry.is_regular_file();
  EXPECT_EQ(files_on_disk, 3u + 6u + 6u);  // parquets, mp4s, meta files
  fs::remove_all(dir);
}

// The packets' presentation times of an mp4 (ffprobe), s.
std::vector<double> frame_times(const std::string& path) {
  const auto probe = testing::run_shell("ffprobe -v error -select_streams v:0 -show_entries packet=pts_time -of csv=p=0 '" + path + "'");
  EXPECT_EQ(probe.exit_code, 0) << probe.output;
  std::vector<double> times;
  std::istringstream in(probe.output);
  std::string line;
  while (std::getline(in, line)) times.push_back(std::stod(line));
  std::sort(times.begin(), times.end());
  return times;
}

TEST(LeRobot, V30DatasetHoldsSeveralEpisodesPerFileWithOffsetsTheReadersAgreeWith) {
  const fs::path dir = temp_dir("lerobot", "v30");
  LeRobotOptions options;
  options.episodes_per_file = 2;  // episodes 0 and 1 in file 0, episode 2 in file 1
  write_dataset(dir, LeRobotVersion::kV30, options);
  EXPECT_FALSE(fs::exists(dir / ".staging"));
  const Json info = core::read_json_file((dir / "meta/info.json").string());
  check_info(info, "v3.0");
  EXPECT_EQ(info.at("data_files_size_in_mb"), 100);
  EXPECT_EQ(info.at("video_files_size_in_mb"), 200);
  EXPECT_EQ(info.at("video_path"), "videos/{video_key}/chunk-{chunk_index:03d}/file-{file_index:03d}.mp4");

  const std::string episodes_file = (dir / "meta/episodes/chunk-000/file-000.parquet").string();
  const std::string tasks_file = (dir / "meta/tasks.parquet").string();
  const std::vector<std::string> data_files = {(dir / "data/chunk-000/file-000.parquet").string(),
                                               (dir / "data/chunk-000/file-001.parquet").string()};
  const Json read = testing::read_with_real_readers({episodes_file, tasks_file, data_files[0], data_files[1]});
  ASSERT_FALSE(read.is_null());

  // tasks.parquet: task_index and the task text, with the pandas index metadata.
  const Json& tasks_read = read.at(tasks_file).at("duckdb");
  EXPECT_EQ(tasks_read.at("types"), Json({{"task_index", "BIGINT"}, {"task", "VARCHAR"}}));
  const Json pandas = Json::parse(tasks_read.at("metadata").at("pandas").get<std::string>());
  EXPECT_EQ(pandas.at("index_columns"), Json({"task"}));
  std::vector<std::string> tasks;
  for (const Json& row : tasks_read.at("rows")) {
    EXPECT_EQ(row.at("task_index"), tasks.size());
    tasks.push_back(row.at("task"));
  }
  EXPECT_EQ(info.at("total_tasks"), tasks.size());

  std::map<int64_t, std::vector<Json>> rows_by_episode;
  for (const std::string& file : data_files) check_rows_and_columns(info, read.at(file), tasks, rows_by_episode);
  EXPECT_EQ(read.at(data_files[0]).at("duckdb").at("rows").size(), 12u);
  EXPECT_EQ(read.at(data_files[1]).at("duckdb").at("rows").size(), 4u);
  check_episode_rows(rows_by_episode, tasks);

  // meta/episodes: offsets into the files, timestamps into the mp4s, stats.
  const Json& episodes = read.at(episodes_file).at("duckdb").at("rows");
  EXPECT_EQ(read.at(episodes_file).at("hyparquet").at("rows"), episodes);
  ASSERT_EQ(episodes.size(), 3u);
  const std::vector<int64_t> file_of = {0, 0, 1};
  const std::vector<int64_t> from = {0, 5, 12};
  const std::vector<double> from_time = {0.0, 0.25, 0.0};
  for (size_t e = 0; e < 3; ++e) {
    SCOPED_TRACE(e);
    const Json& row = episodes[e];
    const int64_t n = kEpisodes[e].second;
    EXPECT_EQ(row.at("episode_index"), e);
    EXPECT_EQ(row.at("tasks"), Json({header(kEpisodes[e].first).instruction}));
    EXPECT_EQ(row.at("length"), n);
    EXPECT_EQ(row.at("data/chunk_index"), 0);
    EXPECT_EQ(row.at("data/file_index"), file_of[e]);
    EXPECT_EQ(row.at("dataset_from_index"), from[e]);
    EXPECT_EQ(row.at("dataset_to_index"), from[e] + n);
    for (const char* camera : {"agentview", "wrist"}) {
      const std::string prefix = std::string("videos/observation.images.") + camera + "/";
      EXPECT_EQ(row.at(prefix + "file_index"), file_of[e]);
      EXPECT_DOUBLE_EQ(row.at(prefix + "from_timestamp").get<double>(), from_time[e]);
      EXPECT_DOUBLE_EQ(row.at(prefix + "to_timestamp").get<double>(), from_time[e] + static_cast<double>(n) / 20);
    }
    EXPECT_EQ(row.at("hribench/spec_hash"), header(kEpisodes[e].first).spec_hash);
    EXPECT_EQ(row.at("hribench/seed"), 1000 + kEpisodes[e].first);
    EXPECT_EQ(row.at("hribench/success"), e != 2);
    const auto& rows = rows_by_episode.at(static_cast<int64_t>(e));
    for (const char* key : {"observation.state", "action", "index"}) {
      Json stats;
      for (const char* s : {"min", "max", "mean", "std", "q01", "q99", "count"}) stats[s] = row.at(std::string("stats/") + key + "/" + s);
      expect_stats(stats, recompute(column_rows(rows, key)), n, key);
    }
  }
  check_dataset_stats(dir, rows_by_episode);
  check_modality(dir);

  // Each mp4 holds its episodes' frames one after the other, frame i at i / fps.
  const std::vector<int64_t> frames = {12, 4};
  for (int64_t file = 0; file < 2; ++file) {
    for (const char* camera : {"agentview", "wrist"}) {
      const std::string path = (dir / fmt::format("videos/observation.images.{}/chunk-000/file-{:03d}.mp4", camera, file)).string();
      const auto video = probe_video(path);
      EXPECT_EQ(video.codec, "h264");
      EXPECT_EQ(video.pix_fmt, "yuv420p");
      EXPECT_EQ(video.width, kWidth);
      EXPECT_EQ(video.frames, frames[static_cast<size_t>(file)]);
      const std::vector<double> times = frame_times(path);
      ASSERT_EQ(static_cast<int64_t>(times.size()), frames[static_cast<size_t>(file)]);
      for (size_t i = 0; i < times.size(); ++i) EXPECT_NEAR(times[i], static_cast<double>(i) / 20, 1e-9);
    }
  }
  // Episode 1's first frame is frame 5 of file 0: the decoded picture is episode 1's, not 0's.
  const std::string rgb = testing::decode_frame_rgb(
      (dir / "videos/observation.images.agentview/chunk-000/file-000.mp4").string(), 5);
  const render::Image first = image(1, 0, 0), other = image(0, 4, 0);
  ASSERT_EQ(rgb.size(), first.rgb.size());
  double error_first = 0, error_other = 0;
  for (size_t i = 0; i < rgb.size(); ++i) {
    error_first += std::abs(static_cast<uint8_t>(rgb[i]) - first.rgb[i]);
    error_other += std::abs(static_cast<uint8_t>(rgb[i]) - other.rgb[i]);
  }
  EXPECT_LT(error_first, error_other / 2);
  fs::remove_all(dir);
}

TEST(LeRobot, ResumeKeepsTheEpisodesTheCollectorCommittedAndAppendsAfterThem) {
  for (const LeRobotVersion version : {LeRobotVersion::kV21, LeRobotVersion::kV30}) {
    SCOPED_TRACE(std::string(to_string(version)));
    const fs::path dir = temp_dir("lerobot", "resume");
    LeRobotOptions options;
    options.episodes_per_file = 1;
    {  // a run that stops mid-episode: episodes 0 and 1 committed, a third one in progress
      auto writer = make_lerobot_writer(dir, version, options);
      commit(*writer, 0, 5);
      commit(*writer, 1, 7);
      auto in_progress = record(*writer, 2, 3);
      // and a file a run stopped between writing it and its meta
      std::ofstream(dir / "data/chunk-000/stray.parquet") << "x";
    }
    // On disk: v2.1 both episodes; v3.0 episode 0's file group, episode 1 staged.
    const Json info = core::read_json_file((dir / "meta/info.json").string());
    EXPECT_EQ(info.at("total_episodes"), version == LeRobotVersion::kV21 ? 2 : 1);
    EXPECT_EQ(error_of([&] { make_lerobot_writer(dir, version, options)->begin_episode(header(2)); }),
              dir.string() + ": expected a folder without a LeRobot dataset (or resume), got one (meta/info.json)");
    const LeRobotVersion other = version == LeRobotVersion::kV21 ? LeRobotVersion::kV30 : LeRobotVersion::kV21;
    EXPECT_EQ(error_of([&] { make_lerobot_writer(dir, other, options)->resume({header(0)}); }),
              (dir / "meta/info.json").string() + ": codebase_version: expected \"" +
                  std::string(to_string(other)) + "\", got \"" + std::string(to_string(version)) + "\"");
    EXPECT_EQ(error_of([&] { make_lerobot_writer(dir, version, options)->resume({header(0), header(1), header(2)}); }),
              dir.string() + ": expected the 3 episodes the collect committed, got 2 in its LeRobot files");
    EXPECT_EQ(error_of([&] { make_lerobot_writer(dir, version, options)->resume({header(1)}); }),
              dir.string() + ": episode 0: expected spec spec1 seed 1001, got spec spec0 seed 1000");
    {  // the collector recorded only episode 0 (it stopped before noting episode 1): 1 is dropped
      auto writer = make_lerobot_writer(dir, version, options);
      writer->resume({header(0)});
      EXPECT_FALSE(fs::exists(dir / "data/chunk-000/stray.parquet"));
      EXPECT_FALSE(fs::exists(dir / "data/chunk-000/episode_000001.parquet"));
      EXPECT_FALSE(fs::exists(dir / ".staging/committed-000001.json"));
      EXPECT_EQ(core::read_json_file((dir / "meta/info.json").string()).at("total_episodes"), 1);
      commit(*writer, 1, 7);  // stopped again after committing 1
    }
    auto writer = make_lerobot_writer(dir, version, options);
    writer->resume({header(0), header(1)});
    commit(*writer, 2, 4);
    writer->finish();
    const Json after = core::read_json_file((dir / "meta/info.json").string());
    EXPECT_EQ(after.at("total_episodes"), 3);
    EXPECT_EQ(after.at("total_frames"), 16);
    EXPECT_FALSE(fs::exists(dir / ".staging"));
    const std::string last = version == LeRobotVersion::kV21 ? "data/chunk-000/episode_000002.parquet"
                                                             : "data/chunk-000/file-002.parquet";
    const ParquetTable table = read_parquet(dir / last);
    EXPECT_EQ(table.find("index")->int64s, (std::vector<int64_t>{12, 13, 14, 15}));
    EXPECT_EQ(table.find("episode_index")->int64s, (std::vector<int64_t>{2, 2, 2, 2}));
    const Json stats = core::read_json_file((dir / "meta/stats.json").string());
    EXPECT_EQ(stats.at("index").at("max"), Json({15.0}));
    EXPECT_EQ(stats.at("index").at("count"), Json({16}));
    // The episodes read back for a replay: annotations and every row's vectors.
    const std::vector<LeRobotEpisode> episodes = read_lerobot_episodes(dir);
    ASSERT_EQ(episodes.size(), 3u);
    for (size_t e = 0; e < 3; ++e) {
      const auto [number, length] = kEpisodes[e];
      const EpisodeHeader h = header(number);
      EXPECT_EQ(episodes[e].index, static_cast<int64_t>(e));
      EXPECT_EQ(episodes[e].spec_hash, h.spec_hash);
      EXPECT_EQ(episodes[e].seed, h.seed);
      EXPECT_EQ(episodes[e].task, h.task);
      EXPECT_EQ(episodes[e].variant, h.variant);
      EXPECT_EQ(episodes[e].action_space, "ee_delta");
      EXPECT_EQ(episodes[e].instruction, h.instruction);
      EXPECT_EQ(episodes[e].success, number != 2);
      ASSERT_EQ(static_cast<int64_t>(episodes[e].actions.size()), length);
      for (int64_t i = 0; i < length; ++i) {
        for (size_t d = 0; d < 7; ++d) EXPECT_EQ(episodes[e].actions[static_cast<size_t>(i)][d], -state_value(number, i, d));
        EXPECT_EQ(episodes[e].states[static_cast<size_t>(i)][7], state_value(number, i, 7));
      }
    }
    EXPECT_EQ(error_of([&] { read_lerobot_episodes(dir / "nothing"); }),
              (dir / "nothing").string() + ": expected a LeRobot dataset, got no meta/info.json");
    if (version == LeRobotVersion::kV30) {  // written file groups are never rewritten
      EXPECT_EQ(error_of([&] { make_lerobot_writer(dir, version, options)->resume({header(0), header(1)}); }),
                dir.string() + ": expected the 2 episodes the collect committed, got 3 in written files");
    }
    size_t mp4s = 0;
    for (const auto& entry : fs::recursive_directory_iterator(dir / "videos")) {
      if (entry.is_regular_file()) {
        ++mp4s;
        EXPECT_EQ(entry.path().extension(), ".mp4");
      }
    }
    EXPECT_EQ(mp4s, 6u);
    fs::remove_all(dir);
  }
}

TEST(LeRobot, StoredEpisodesCommittedByAnotherWriterGiveTheSameDatasetByteForByte) {
  for (const LeRobotVersion version : {LeRobotVersion::kV21, LeRobotVersion::kV30}) {
    SCOPED_TRACE(std::string(to_string(version)));
    LeRobotOptions options;
    options.episodes_per_file = 2;
    const fs::path direct = temp_dir("lerobot", "stored_direct");
    write_dataset(direct, version, options);
    // Another writer records and stores the episodes (as a shard does), out of order; a third
    // one loads and commits them in order.
    const fs::path scratch = temp_dir("lerobot", "stored_scratch");
    const fs::path stored = temp_dir("lerobot", "stored_episodes");
    {
      auto recorder = make_lerobot_writer(scratch, version, options);
      for (size_t e = kEpisodes.size(); e-- > 0;) {
        recorder->store(record(*recorder, kEpisodes[e].first, kEpisodes[e].second), stored / std::to_string(e));
      }
    }
    EXPECT_FALSE(fs::exists(scratch / "meta/info.json"));
    const fs::path merged = temp_dir("lerobot", "stored_merged");
    auto writer = make_lerobot_writer(merged, version, options);
    for (size_t e = 0; e < kEpisodes.size(); ++e) {
      EpisodeOutcome outcome;
      outcome.success = kEpisodes[e].first != 2;
      outcome.frames = kEpisodes[e].second;
      if (!outcome.success) outcome.failure_labels = {"timeout"};
      writer->commit(writer->load(stored / std::to_string(e)), outcome);
    }
    writer->finish();
    testing::expect_same_files(merged, direct);
    // Loading leaves the stored episode as it was; a folder without one is refused.
    EXPECT_TRUE(fs::exists(stored / "0" / "episode.json"));
    EXPECT_TRUE(fs::exists(stored / "0" / "agentview.mp4"));
    const fs::path empty = temp_dir("lerobot", "stored_none");
    EXPECT_EQ(error_of([&] { make_lerobot_writer(merged, version, options)->load(empty); }),
              (empty / "episode.json").string() + ": cannot open file");
    fs::create_directories(empty);
    std::ofstream(empty / "episode.json") << R"({"format": "act-hdf5"})";
    EXPECT_EQ(error_of([&] { make_lerobot_writer(temp_dir("lerobot", "stored_other"), version, options)->load(empty); }),
              (empty / "episode.json").string() + ": expected an episode stored by the LeRobot writer, got other JSON");
  }
}

TEST(LeRobot, BadFramesAndEpisodesAreInputErrors) {
  const fs::path dir = temp_dir("lerobot", "errors");
  auto writer = make_lerobot_writer(dir, LeRobotVersion::kV21);
  const EpisodeHeader h = header(0);
  auto sink = writer->begin_episode(h);
  const render::Image good = image(0, 0, 0);
  render::Image small;
  small.resize(16, 16);
  Frame frame;
  frame.state.assign(8, 0.0f);
  frame.action.assign(7, 0.0f);
  frame.images = {&good, &small};
  const std::string where = "episode (task point_pick, spec spec0) frame 0";
  EXPECT_EQ(error_of([&] { sink->add(frame); }),
            where + ": camera wrist: expected an RGB image of 64x48, got 16x16 (768 bytes)");
  frame.images = {&good};
  EXPECT_EQ(error_of([&] { sink->add(frame); }), where + ": expected 2 images (one per camera), got 1");
  frame.images = {&good, &good};
  frame.state.assign(9, 0.0f);
  EXPECT_EQ(error_of([&] { sink->add(frame); }),
            where + ": state: expected 8 values (the header's state names), got 9");
  frame.state.assign(8, 0.0f);
  frame.index = 3;
  EXPECT_EQ(error_of([&] { sink->add(frame); }), where + ": expected frame index 0, got 3");
  EXPECT_EQ(error_of([&] { writer->commit(std::move(sink), EpisodeOutcome{}); }),
            "episode (task point_pick, spec spec0): expected an outcome of its 0 frames (at least 1), got 0 frames");
  EpisodeHeader more = header(1);
  more.state_names.push_back("extra");
  commit(*writer, 0, 2);
  EXPECT_EQ(error_of([&] { writer->begin_episode(more); }),
            "episode (task handover, spec spec1): expected the dataset's fps 20, robot panda and features "
            "(meta/info.json), got observation.state of shape [9]");
  more = header(1);
  more.cameras[1].name = "side";
  EXPECT_EQ(error_of([&] { writer->begin_episode(more); }),
            "episode (task handover, spec spec1): expected the dataset's fps 20, robot panda and features "
            "(meta/info.json), got a new feature observation.images.side");
  LeRobotOptions bad;
  bad.chunks_size = 0;
  EXPECT_EQ(error_of([&] { make_lerobot_writer(dir / "other", LeRobotVersion::kV30, bad); }),
            "LeRobot option chunks_size: expected at least 1, got 0");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hribench::io
