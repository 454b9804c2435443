#include "io/lerobot.h"

extern "C" {
#include <libavformat/avformat.h>
}

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "core/errors.h"
#include "core/files.h"
#include "core/json.h"
#include "io/parquet.h"

namespace hribench::io {

using core::Json;
namespace fs = std::filesystem;

namespace {

// Feature keys (docs/datasets.md).
constexpr const char* kState = "observation.state";
constexpr const char* kAction = "action";
constexpr const char* kReward = "next.reward";
constexpr const char* kDone = "next.done";
constexpr const char* kHumanAct = "annotation.human.act";
constexpr const char* kHumanEvents = "annotation.human.events";
constexpr const char* kNone = "none";  // the annotation text of "no act" and "no event"

std::string video_key(const std::string& camera) { return "observation.images." + camera; }

std::string av_error(int code) {
  std::array<char, AV_ERROR_MAX_STRING_SIZE> text{};
  av_strerror(code, text.data(), text.size());
  return text.data();
}

// ---------------------------------------------------------------------------------------------
// Statistics (LeRobot's compute_stats.py): per dimension min, max, mean, population std, the 1st
// and 99th percentiles (numpy's linear interpolation; GR00T's stats.json requires them) and the
// frame count; images per channel scaled to [0, 1], written with shape (3, 1, 1).

constexpr size_t kStatCount = 6;
constexpr std::array<const char*, kStatCount> kStatNames = {"min", "max", "mean", "std", "q01", "q99"};

struct FeatureStats {
  std::vector<double> min, max, mean, std, q01, q99;
  int64_t count = 0;

  std::array<std::vector<double>*, kStatCount> vectors() { return {&min, &max, &mean, &std, &q01, &q99}; }
  std::array<const std::vector<double>*, kStatCount> vectors() const {
    return {&min, &max, &mean, &std, &q01, &q99};
  }
};

// The q-quantile of `count` sorted values, value(k) giving the k-th (numpy's "linear").
template <typename Value>
double quantile(double q, int64_t count, const Value& value) {
  const double position = q * static_cast<double>(count - 1);
  const auto below = static_cast<int64_t>(std::floor(position));
  const double fraction = position - static_cast<double>(below);
  const double low = value(below);
  return below + 1 < count ? low + fraction * (value(below + 1) - low) : low;
}
using EpisodeStats = std::map<std::string, FeatureStats>;

// The stats of a table column: one entry per list element (a scalar column has one dimension).
FeatureStats column_stats(const ParquetColumn& column) {
  const int64_t rows = column.rows();
  const int64_t dims = column.list && rows > 0 ? column.list_lengths.front() : 1;
  FeatureStats stats;
  stats.count = rows;
  stats.min.assign(static_cast<size_t>(dims), std::numeric_limits<double>::infinity());
  stats.max.assign(static_cast<size_t>(dims), -std::numeric_limits<double>::infinity());
  std::vector<double> sum(static_cast<size_t>(dims), 0.0);
  std::vector<double> sum_squares(static_cast<size_t>(dims), 0.0);
  for (int64_t i = 0; i < rows * dims; ++i) {
    const auto k = static_cast<size_t>(i);
    double value = 0;
    switch (column.type) {
      case ParquetType::kInt64:
        value = static_cast<double>(column.int64s[k]);
        break;
      case ParquetType::kFloat32:
        value = static_cast<double>(column.float32s[k]);
        break;
      case ParquetType::kFloat64:
        value = column.float64s[k];
        break;
      case ParquetType::kBool:
        value = column.bools[k] ? 1.0 : 0.0;
        break;
      case ParquetType::kString:
        break;
    }
    const auto d = static_cast<size_t>(i % dims);
    stats.min[d] = std::min(stats.min[d], value);
    stats.max[d] = std::max(stats.max[d], value);
    sum[d] += value;
    sum_squares[d] += value * value;
  }
  std::vector<double> sorted(static_cast<size_t>(rows));
  for (size_t d = 0; d < sum.size(); ++d) {
    const double n = static_cast<double>(rows);
    const double mean = sum[d] / n;
    stats.mean.push_back(mean);
    stats.std.push_back(std::sqrt(std::max(0.0, sum_squares[d] / n - mean * mean)));
    for (int64_t r = 0; r < rows; ++r) {
      const auto k = static_cast<size_t>(r * dims) + d;
      switch (column.type) {
        case ParquetType::kInt64:
          sorted[static_cast<size_t>(r)] = static_cast<double>(column.int64s[k]);
          break;
        case ParquetType::kFloat32:
          sorted[static_cast<size_t>(r)] = static_cast<double>(column.float32s[k]);
          break;
        case ParquetType::kFloat64:
          sorted[static_cast<size_t>(r)] = column.float64s[k];
          break;
        case ParquetType::kBool:
          sorted[static_cast<size_t>(r)] = column.bools[k] ? 1.0 : 0.0;
          break;
        case ParquetType::kString:
          break;
      }
    }
    std::sort(sorted.begin(), sorted.end());
    const auto value = [&sorted](int64_t k) { return sorted[static_cast<size_t>(k)]; };
    stats.q01.push_back(quantile(0.01, rows, value));
    stats.q99.push_back(quantile(0.99, rows, value));
  }
  return stats;
}

// Per-channel histograms of one camera's frames (exact, and cheaper per pixel than running
// sums, minima and maxima).
struct ImageSums {
  std::array<std::array<uint64_t, 256>, 3> histogram{};
  int64_t frames = 0;

  void add(const render::Image& image) {
    const uint8_t* pixel = image.rgb.data();
    const uint8_t* end = pixel + image.rgb.size();
    for (; pixel < end; pixel += 3) {
      ++histogram[0][pixel[0]];
      ++histogram[1][pixel[1]];
      ++histogram[2][pixel[2]];
    }
    ++frames;
  }

  FeatureStats stats() const {
    FeatureStats stats;
    stats.count = frames;
    for (const auto& channel : histogram) {
      uint64_t n = 0, sum = 0, sum_squares = 0;
      int lowest = 255, highest = 0;
      for (int v = 0; v < 256; ++v) {
        const uint64_t k = channel[static_cast<size_t>(v)];
        if (k == 0) continue;
        n += k;
        sum += k * static_cast<uint64_t>(v);
        sum_squares += k * static_cast<uint64_t>(v * v);
        lowest = std::min(lowest, v);
        highest = std::max(highest, v);
      }
      const double count = static_cast<double>(n);
      const double mean = static_cast<double>(sum) / count;
      const double variance = std::max(0.0, static_cast<double>(sum_squares) / count - mean * mean);
      stats.min.push_back(lowest / 255.0);
      stats.max.push_back(highest / 255.0);
      stats.mean.push_back(mean / 255.0);
      stats.std.push_back(std::sqrt(variance) / 255.0);
      const auto value = [&channel](int64_t k) {  // the k-th smallest pixel value
        uint64_t seen = 0;
        for (size_t v = 0; v < 256; ++v) {
          seen += channel[v];
          if (seen > static_cast<uint64_t>(k)) return static_cast<double>(v);
        }
        return 255.0;
      };
      stats.q01.push_back(quantile(0.01, static_cast<int64_t>(n), value) / 255.0);
      stats.q99.push_back(quantile(0.99, static_cast<int64_t>(n), value) / 255.0);
    }
    return stats;
  }
};

// Dataset statistics from the episodes' (LeRobot's aggregate_stats): weighted means, the pooled
// population variance.
FeatureStats aggregate(const std::vector<const FeatureStats*>& parts) {
  FeatureStats total = *parts.front();
  const size_t dims = total.mean.size();
  total.count = 0;
  for (const FeatureStats* part : parts) total.count += part->count;
  std::vector<double> mean(dims, 0.0);
  for (const FeatureStats* part : parts) {
    for (size_t d = 0; d < dims; ++d) {
      total.min[d] = std::min(total.min[d], part->min[d]);
      total.max[d] = std::max(total.max[d], part->max[d]);
      mean[d] += part->mean[d] * static_cast<double>(part->count) / static_cast<double>(total.count);
    }
  }
  // Quantiles: the count-weighted mean of the episodes' (as LeRobot aggregates them; exact
  // ones would need every value of the dataset).
  for (size_t d = 0; d < dims; ++d) {
    double q01 = 0, q99 = 0;
    for (const FeatureStats* part : parts) {
      const double weight = static_cast<double>(part->count) / static_cast<double>(total.count);
      q01 += part->q01[d] * weight;
      q99 += part->q99[d] * weight;
    }
    total.q01[d] = q01;
    total.q99[d] = q99;
  }
  for (size_t d = 0; d < dims; ++d) {
    double variance = 0;
    for (const FeatureStats* part : parts) {
      const double delta = part->mean[d] - mean[d];
      variance += static_cast<double>(part->count) * (part->std[d] * part->std[d] + delta * delta);
    }
    total.mean[d] = mean[d];
    total.std[d] = std::sqrt(variance / static_cast<double>(total.count));
  }
  return total;
}

Json stats_json(const FeatureStats& stats, bool image) {
  const auto values = [image](const std::vector<double>& v) {
    Json out = Json::array();
    for (double x : v) out.push_back(image ? Json::array({Json::array({x})}) : Json(x));
    return out;
  };
  Json json = {{"count", Json::array({stats.count})}};
  for (size_t s = 0; s < kStatCount; ++s) json[kStatNames[s]] = values(*stats.vectors()[s]);
  return json;
}

void flatten_numbers(const Json& value, std::vector<double>& out, const std::string& where) {
  if (value.is_array()) {
    for (const Json& item : value) flatten_numbers(item, out, where);
  } else {
    out.push_back(core::json_number(value, where));
  }
}

FeatureStats stats_from_json(const Json& json, const std::string& where) {
  FeatureStats stats;
  for (size_t s = 0; s < kStatCount; ++s) {
    flatten_numbers(core::json_member(json, kStatNames[s], where), *stats.vectors()[s],
                    where + "." + kStatNames[s]);
  }
  std::vector<double> count;
  flatten_numbers(core::json_member(json, "count", where), count, where + ".count");
  if (count.size() != 1) throw core::InputError(where + ".count", "[n]", json["count"].dump());
  stats.count = static_cast<int64_t>(count.front());
  return stats;
}

// ---------------------------------------------------------------------------------------------
// Features and GR00T's modality groups.

Json features_of(const EpisodeHeader& header) {
  const auto scalar = [](const char* dtype) {
    return Json{{"dtype", dtype}, {"shape", {1}}, {"names", nullptr}};
  };
  Json features = Json::object();
  for (const CameraSpec& camera : header.cameras) {
    features[video_key(camera.name)] = {
        {"dtype", "video"},
        {"shape", {camera.height, camera.width, 3}},
        {"names", {"height", "width", "channels"}},
        {"info",
         {{"video.fps", header.fps},
          {"video.height", camera.height},
          {"video.width", camera.width},
          {"video.channels", 3},
          {"video.codec", "h264"},
          {"video.pix_fmt", "yuv420p"},
          {"video.is_depth_map", false},
          {"has_audio", false}}}};
  }
  features[kState] = {{"dtype", "float32"},
                      {"shape", {header.state_names.size()}},
                      {"names", header.state_names}};
  features[kAction] = {{"dtype", "float32"},
                       {"shape", {header.action_names.size()}},
                       {"names", header.action_names}};
  features[kReward] = scalar("float32");
  features[kDone] = scalar("bool");
  features[kHumanAct] = scalar("int64");
  features[kHumanEvents] = scalar("int64");
  features["timestamp"] = scalar("float32");
  for (const char* key : {"frame_index", "episode_index", "index", "task_index"}) {
    features[key] = scalar("int64");
  }
  return features;
}

std::vector<std::string> names_of(const Json& features, const char* key) {
  std::vector<std::string> names;
  for (const Json& name : features.at(key).at("names")) names.push_back(name.get<std::string>());
  return names;
}

std::vector<std::string> cameras_of(const Json& features) {
  std::vector<std::string> cameras;
  const std::string prefix = "observation.images.";
  for (const auto& [key, feature] : features.items()) {
    if (feature.at("dtype") == "video") cameras.push_back(key.substr(prefix.size()));
  }
  return cameras;
}

// GR00T's state or action groups: consecutive dimensions of one group form one [start, end)
// slice, so the slices cover the vector exactly, in order (docs/datasets.md). A name's group is
// its GROUP of GROUP.PART (io/recording.h), else the name without a trailing index
// ("joint_3" -> "joint", "q[2]" -> "q").
Json modality_groups(const std::vector<std::string>& names) {
  const auto stem = [](const std::string& name) {
    if (const size_t dot = name.find('.'); dot != std::string::npos && dot > 0) return name.substr(0, dot);
    size_t end = name.size();
    if (end > 0 && name[end - 1] == ']') --end;
    while (end > 0 && std::isdigit(static_cast<unsigned char>(name[end - 1])) != 0) --end;
    while (end > 0 && (name[end - 1] == '_' || name[end - 1] == '.' || name[end - 1] == '[')) {
      --end;
    }
    return end == 0 ? name : name.substr(0, end);
  };
  Json groups = Json::object();
  size_t start = 0;
  while (start < names.size()) {
    const std::string group = stem(names[start]);
    size_t end = start + 1;
    while (end < names.size() && stem(names[end]) == group) ++end;
    std::string key = group;
    for (int n = 2; groups.contains(key); ++n) key = group + "_" + std::to_string(n);
    groups[key] = {{"start", start}, {"end", end}};
    start = end;
  }
  return groups;
}

Json modality_of(const Json& features) {
  Json modality = {{"state", modality_groups(names_of(features, kState))},
                   {"action", modality_groups(names_of(features, kAction))},
                   {"video", Json::object()},
                   {"annotation",
                    {{"human.task_description", {{"original_key", "task_index"}}},
                     {"human.act", {{"original_key", kHumanAct}}},
                     {"human.events", {{"original_key", kHumanEvents}}}}}};
  for (const std::string& camera : cameras_of(features)) {
    modality["video"][camera] = {{"original_key", video_key(camera)}};
  }
  return modality;
}

// ---------------------------------------------------------------------------------------------
// One committed episode.

struct EpisodeRecord {
  int64_t index = 0;
  int64_t length = 0;
  std::string instruction;
  // HRIBench's annotations of the episode (docs/datasets.md).
  std::string task, task_id, role, spec_hash, policy, action_space, status;
  uint64_t seed = 0;
  std::string variant;
  bool success = false;
  std::vector<std::string> failure_labels;
  EpisodeStats stats;
  // v3.0: where its rows and frames are.
  int64_t group = 0;          // the file group (chunk group / chunks_size, file group % it)
  int64_t from_index = 0;     // its first row's global index
  int64_t from_frame = 0;     // its first frame's number in the group's mp4s (at from_frame / fps)
};

Json annotations_json(const EpisodeRecord& r) {
  return {{"task", r.task},     {"task_id", r.task_id}, {"role", r.role},
          {"spec_hash", r.spec_hash}, {"seed", r.seed},   {"variant", r.variant},
          {"policy", r.policy}, {"action_space", r.action_space},
          {"success", r.success}, {"status", r.status}, {"failure_labels", r.failure_labels}};
}

void read_annotations(const Json& json, const std::string& where, EpisodeRecord& r) {
  r.task = core::json_string(core::json_member(json, "task", where), where + ".task");
  r.task_id = core::json_string(core::json_member(json, "task_id", where), where + ".task_id");
  r.role = core::json_string(core::json_member(json, "role", where), where + ".role");
  r.spec_hash = core::json_string(core::json_member(json, "spec_hash", where), where + ".spec_hash");
  r.seed = core::json_member(json, "seed", where).get<uint64_t>();
  r.variant = core::json_string(core::json_member(json, "variant", where), where + ".variant");
  r.policy = core::json_string(core::json_member(json, "policy", where), where + ".policy");
  r.action_space =
      core::json_string(core::json_member(json, "action_space", where), where + ".action_space");
  r.success = core::json_bool(core::json_member(json, "success", where), where + ".success");
  r.status = core::json_string(core::json_member(json, "status", where), where + ".status");
  r.failure_labels = core::json_member(json, "failure_labels", where).get<std::vector<std::string>>();
}

// ---------------------------------------------------------------------------------------------
// Parquet table helpers.

void append_rows(ParquetTable& into, const ParquetTable& from) {
  if (into.columns.empty()) {
    into = from;
    return;
  }
  for (size_t c = 0; c < from.columns.size(); ++c) {
    ParquetColumn& a = into.columns[c];
    const ParquetColumn& b = from.columns[c];
    a.int64s.insert(a.int64s.end(), b.int64s.begin(), b.int64s.end());
    a.float32s.insert(a.float32s.end(), b.float32s.begin(), b.float32s.end());
    a.float64s.insert(a.float64s.end(), b.float64s.begin(), b.float64s.end());
    a.bools.insert(a.bools.end(), b.bools.begin(), b.bools.end());
    a.strings.insert(a.strings.end(), b.strings.begin(), b.strings.end());
    a.list_lengths.insert(a.list_lengths.end(), b.list_lengths.begin(), b.list_lengths.end());
  }
}

// About the bytes write_parquet writes for `table` (values and levels), for the rollover.
int64_t estimated_bytes(const ParquetTable& table) {
  int64_t bytes = 0;
  for (const ParquetColumn& column : table.columns) {
    bytes += 8 * static_cast<int64_t>(column.int64s.size() + column.float64s.size()) +
             4 * static_cast<int64_t>(column.float32s.size()) +
             static_cast<int64_t>(column.bools.size()) / 8 + 4 * static_cast<int64_t>(column.list_lengths.size());
    for (const std::string& s : column.strings) bytes += 4 + static_cast<int64_t>(s.size());
  }
  return bytes;
}

const ParquetColumn& column_of(const ParquetTable& table, const std::string& name,
                               const std::string& where) {
  const ParquetColumn* column = table.find(name);
  if (column == nullptr) throw core::InputError(where, "a column " + name, "none");
  return *column;
}

// ---------------------------------------------------------------------------------------------
// Videos of several episodes in one mp4: the episodes' H.264 packets copied one after the other
// (no re-encoding), episode k's frame j at (frames before k + j) / fps.

void concatenate_videos(const std::vector<fs::path>& parts, const std::vector<int64_t>& frames,
                        const fs::path& out, int fps) {
  const fs::path temporary = out.string() + ".tmp";
  const std::string where = out.string();
  AVFormatContext* output = nullptr;
  AVPacket* packet = av_packet_alloc();
  AVFormatContext* input = nullptr;
  const auto cleanup = [&] {
    if (input != nullptr) avformat_close_input(&input);
    if (output != nullptr) {
      if (output->pb != nullptr) avio_closep(&output->pb);
      avformat_free_context(output);
      output = nullptr;
    }
    av_packet_free(&packet);
  };
  try {
    const auto check = [&](int code, const std::string& what) {
      if (code < 0) throw core::InputError::Message(where, "cannot write the video: " + what + ": " + av_error(code));
    };
    check(avformat_alloc_output_context2(&output, nullptr, "mp4", nullptr), "mp4 muxer");
    AVStream* stream = nullptr;
    const AVRational frame_base{1, fps};
    int64_t offset = 0;
    for (size_t p = 0; p < parts.size(); ++p) {
      check(avformat_open_input(&input, parts[p].c_str(), nullptr, nullptr), "open " + parts[p].string());
      check(avformat_find_stream_info(input, nullptr), "read " + parts[p].string());
      const int index = av_find_best_stream(input, AVMEDIA_TYPE_VIDEO, -1, -1, nullptr, 0);
      check(index, "a video stream in " + parts[p].string());
      const AVStream* in = input->streams[index];
      if (stream == nullptr) {
        stream = avformat_new_stream(output, nullptr);
        if (stream == nullptr) check(AVERROR(ENOMEM), "new stream");
        check(avcodec_parameters_copy(stream->codecpar, in->codecpar), "codec parameters");
        stream->codecpar->codec_tag = 0;
        stream->time_base = frame_base;
        stream->avg_frame_rate = AVRational{fps, 1};
        check(avio_open(&output->pb, temporary.c_str(), AVIO_FLAG_WRITE), "open " + temporary.string());
        check(avformat_write_header(output, nullptr), "header");
      } else if (in->codecpar->width != stream->codecpar->width ||
                 in->codecpar->height != stream->codecpar->height ||
                 in->codecpar->extradata_size != stream->codecpar->extradata_size ||
                 !std::equal(in->codecpar->extradata,
                             in->codecpar->extradata + in->codecpar->extradata_size,
                             stream->codecpar->extradata)) {
        throw core::InputError(parts[p].string(), "the encoder settings of the file's first episode",
                               "others");
      }
      int64_t packets = 0;
      while (av_read_frame(input, packet) >= 0) {
        if (packet->stream_index == index) {
          const auto place = [&](int64_t t) {
            return av_rescale_q(av_rescale_q(t, in->time_base, frame_base) + offset, frame_base,
                                stream->time_base);
          };
          packet->pts = place(packet->pts);
          packet->dts = place(packet->dts);
          packet->duration = av_rescale_q(1, frame_base, stream->time_base);
          packet->stream_index = 0;
          packet->pos = -1;
          ++packets;
          check(av_write_frame(output, packet), "frame");
        }
        av_packet_unref(packet);
      }
      avformat_close_input(&input);
      if (packets != frames[p]) {
        throw core::InputError(parts[p].string(), std::to_string(frames[p]) + " frames",
                               std::to_string(packets));
      }
      offset += packets;
    }
    check(av_write_trailer(output), "trailer");
    cleanup();
    std::error_code error;
    fs::rename(temporary, out, error);
    if (error) throw core::InputError::Message(where, "cannot write the video: " + error.message());
  } catch (...) {
    cleanup();
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw;
  }
}

// ---------------------------------------------------------------------------------------------
// One episode being recorded: its rows in memory, its frames encoded into staging mp4s.

class LeRobotSink : public EpisodeSink {
 public:
  LeRobotSink(EpisodeHeader header_in, const fs::path& staging, int64_t id,
              const VideoSettings& video)
      : header(std::move(header_in)),
        where_("episode (task " + header.task + ", spec " + header.spec_hash + ")") {
    VideoSettings settings = video;
    settings.fps = header.fps;
    for (const CameraSpec& camera : header.cameras) {
      video_paths.push_back(staging / fmt::format("episode-{}-{}.mp4", id, camera.name));
      videos.push_back(
          std::make_unique<VideoWriter>(video_paths.back(), camera.width, camera.height, settings));
      image_sums.emplace_back();
    }
  }

  // A stored episode being loaded (DatasetWriter::load): the caller fills the rows and copies
  // the mp4s; nothing is encoded.
  LeRobotSink(EpisodeHeader header_in, const std::string& stored)
      : header(std::move(header_in)), where_("episode stored in " + stored), finished_(true) {}

  ~LeRobotSink() override {
    videos.clear();  // unfinished writers remove their temporary files
    if (!placed) {
      std::error_code ignored;
      for (const fs::path& path : video_paths) fs::remove(path, ignored);
    }
  }

  void add(const Frame& frame) override {
    const std::string where = where_ + " frame " + std::to_string(rows);
    if (frame.index != rows) {
      throw core::InputError(where, "frame index " + std::to_string(rows),
                             std::to_string(frame.index));
    }
    const auto check_size = [&](const std::vector<float>& values, const std::vector<std::string>& names,
                                const char* what) {
      if (values.size() != names.size()) {
        throw core::InputError(where + ": " + what,
                               fmt::format("{} values (the header's {} names)", names.size(), what),
                               std::to_string(values.size()));
      }
    };
    check_size(frame.state, header.state_names, "state");
    check_size(frame.action, header.action_names, "action");
    if (frame.images.size() != header.cameras.size()) {
      throw core::InputError(where, fmt::format("{} images (one per camera)", header.cameras.size()),
                             std::to_string(frame.images.size()));
    }
    for (size_t c = 0; c < header.cameras.size(); ++c) {
      const CameraSpec& camera = header.cameras[c];
      const render::Image* image = frame.images[c];
      if (image == nullptr || image->width != camera.width || image->height != camera.height ||
          image->rgb.size() != static_cast<size_t>(camera.width) * static_cast<size_t>(camera.height) * 3) {
        throw core::InputError(
            where + ": camera " + camera.name,
            fmt::format("an RGB image of {}x{}", camera.width, camera.height),
            image == nullptr ? "none" : fmt::format("{}x{} ({} bytes)", image->width, image->height, image->rgb.size()));
      }
    }
    for (size_t c = 0; c < header.cameras.size(); ++c) {
      videos[c]->add(*frame.images[c]);
      image_sums[c].add(*frame.images[c]);
    }
    states.insert(states.end(), frame.state.begin(), frame.state.end());
    actions.insert(actions.end(), frame.action.begin(), frame.action.end());
    rewards.push_back(frame.reward);
    dones.push_back(frame.done);
    acts.push_back(frame.human_act.empty() ? kNone : frame.human_act);
    std::string events_text;
    for (const std::string& event : frame.events) {
      events_text += (events_text.empty() ? "" : "; ") + event;
    }
    events.push_back(events_text.empty() ? kNone : events_text);
    ++rows;
    if (frame.done) finish_videos();  // flush the encoders on the worker thread
  }

  void finish_videos() {
    for (const auto& video : videos) {
      if (video->frames() > 0 && !finished_) video->finish();
    }
    finished_ = true;
  }

  const std::string& where() const { return where_; }

  EpisodeHeader header;
  int64_t rows = 0;
  std::vector<float> states, actions, rewards;
  std::vector<bool> dones;
  std::vector<std::string> acts, events;
  std::vector<ImageSums> image_sums;
  std::vector<std::unique_ptr<VideoWriter>> videos;
  std::vector<fs::path> video_paths;
  bool placed = false;  // the mp4s were moved into the dataset (or into a file group)

 private:
  std::string where_;
  bool finished_ = false;
};

// ---------------------------------------------------------------------------------------------

class LeRobotWriter : public DatasetWriter {
 public:
  LeRobotWriter(fs::path dir, LeRobotVersion version, const LeRobotOptions& options)
      : dir_(std::move(dir)), version_(version), options_(options) {
    const auto at_least_one = [&](int64_t value, const char* name) {
      if (value < 1) {
        throw core::InputError(std::string("LeRobot option ") + name, "at least 1",
                               std::to_string(value));
      }
    };
    at_least_one(options.chunks_size, "chunks_size");
    at_least_one(options.data_file_size_mb, "data_file_size_mb");
    at_least_one(options.video_file_size_mb, "video_file_size_mb");
    at_least_one(options.episodes_per_file, "episodes_per_file");
  }

  void resume(const std::vector<EpisodeHeader>& committed) override {
    std::lock_guard lock(mutex_);
    HRIB_CHECK(!opened_) << "resume is called once, before any episode";
    opened_ = true;
    if (fs::exists(dir_ / "meta/info.json")) load();
    if (committed.size() > episodes_.size()) {
      throw core::InputError(dir_.string(),
                             fmt::format("the {} episodes the collect committed", committed.size()),
                             fmt::format("{} in its LeRobot files", episodes_.size()));
    }
    for (size_t e = 0; e < committed.size(); ++e) {
      if (committed[e].spec_hash != episodes_[e].spec_hash || committed[e].seed != episodes_[e].seed) {
        throw core::InputError(dir_.string() + ": episode " + std::to_string(e),
                               "spec " + committed[e].spec_hash + " seed " + std::to_string(committed[e].seed),
                               "spec " + episodes_[e].spec_hash + " seed " + std::to_string(episodes_[e].seed));
      }
    }
    // Episodes written after the last one the collector recorded are dropped.
    if (committed.size() < written_) {
      if (version_ == LeRobotVersion::kV30) {
        throw core::InputError(dir_.string(), fmt::format("the {} episodes the collect committed", committed.size()),
                               fmt::format("{} in written files", written_));
      }
      written_ = committed.size();
    }
    episodes_.resize(committed.size());
    if (version_ == LeRobotVersion::kV30 && !features_.is_null()) reload_group();
    total_frames_ = 0;
    for (const EpisodeRecord& record : episodes_) total_frames_ += record.length;
    remove_unlisted_files();
    if (!features_.is_null()) write_meta();
  }

  std::unique_ptr<EpisodeSink> begin_episode(const EpisodeHeader& header) override {
    accept(header);
    fs::create_directories(staging());
    return std::make_unique<LeRobotSink>(header, staging(), next_sink_++, options_.video);
  }

  // The rows in episode.json (header, rows, image histograms), the mp4s as CAMERA.mp4.
  void store(std::unique_ptr<EpisodeSink> sink_in, const fs::path& folder) override {
    auto& sink = dynamic_cast<LeRobotSink&>(*sink_in);
    sink.finish_videos();
    fs::create_directories(folder);
    for (size_t c = 0; c < sink.video_paths.size(); ++c) {
      fs::rename(sink.video_paths[c], folder / (sink.header.cameras[c].name + ".mp4"));
    }
    sink.placed = true;
    Json histograms = Json::array();
    for (const ImageSums& sums : sink.image_sums) histograms.push_back({{"frames", sums.frames}, {"rgb", sums.histogram}});
    const Json stored = {{"format", "lerobot"},
                         {"header", episode_header_json(sink.header)},
                         {"rows", sink.rows},
                         {"states", sink.states},
                         {"actions", sink.actions},
                         {"rewards", sink.rewards},
                         {"dones", sink.dones},
                         {"acts", sink.acts},
                         {"events", sink.events},
                         {"image_histograms", histograms}};
    core::write_file_atomically(folder / "episode.json", stored.dump() + "\n");
  }

  std::unique_ptr<EpisodeSink> load(const fs::path& folder) override {
    const std::string where = (folder / "episode.json").string();
    const Json stored = core::read_json_file(where);
    if (!stored.is_object() || stored.value("format", Json()) != "lerobot") {
      throw core::InputError(where, "an episode stored by the LeRobot writer", "other JSON");
    }
    EpisodeHeader header = episode_header_from_json(core::json_member(stored, "header", where), where + ": header");
    accept(header);
    fs::create_directories(staging());
    auto sink = std::make_unique<LeRobotSink>(std::move(header), where);
    try {
      sink->rows = stored.at("rows").get<int64_t>();
      sink->states = stored.at("states").get<std::vector<float>>();
      sink->actions = stored.at("actions").get<std::vector<float>>();
      sink->rewards = stored.at("rewards").get<std::vector<float>>();
      sink->dones = stored.at("dones").get<std::vector<bool>>();
      sink->acts = stored.at("acts").get<std::vector<std::string>>();
      sink->events = stored.at("events").get<std::vector<std::string>>();
      for (const Json& h : stored.at("image_histograms")) {
        ImageSums sums;
        sums.frames = h.at("frames").get<int64_t>();
        sums.histogram = h.at("rgb").get<decltype(sums.histogram)>();
        sink->image_sums.push_back(sums);
      }
    } catch (const Json::exception& e) {
      throw core::InputError(where, "an episode stored by the LeRobot writer", e.what());
    }
    const size_t rows = static_cast<size_t>(sink->rows);
    if (sink->rows < 0 || sink->states.size() != rows * sink->header.state_names.size() ||
        sink->actions.size() != rows * sink->header.action_names.size() || sink->rewards.size() != rows ||
        sink->dones.size() != rows || sink->acts.size() != rows || sink->events.size() != rows ||
        sink->image_sums.size() != sink->header.cameras.size()) {
      throw core::InputError(where, fmt::format("the rows and histograms of {} frames", sink->rows), "others");
    }
    const int64_t id = next_sink_++;
    for (const CameraSpec& camera : sink->header.cameras) {
      const fs::path from = folder / (camera.name + ".mp4");
      sink->video_paths.push_back(staging() / fmt::format("episode-{}-{}.mp4", id, camera.name));
      std::error_code error;
      fs::copy_file(from, sink->video_paths.back(), fs::copy_options::overwrite_existing, error);
      if (error) throw core::InputError::Message(from.string(), "cannot be copied: " + error.message());
    }
    return sink;
  }

 private:
  // Checks that an episode of `header` fits the dataset (its first episode sets the features).
  void accept(const EpisodeHeader& header) {
    {
      std::lock_guard lock(mutex_);
      open_new();
      const Json features = features_of(header);
      if (features_.is_null()) {
        features_ = features;
        fps_ = header.fps;
        robot_ = header.robot;
      } else if (features != features_ || header.fps != fps_ || header.robot != robot_) {
        std::string got = fmt::format("fps {}, robot {}", header.fps, header.robot);
        for (const auto& [key, feature] : features.items()) {
          if (!features_.contains(key)) {
            got = "a new feature " + key;
            break;
          }
          if (features_[key] != feature) {
            got = features_[key].at("shape") != feature.at("shape")
                      ? key + " of shape " + feature.at("shape").dump()
                      : "other names or video info of " + key;
            break;
          }
        }
        for (const auto& [key, feature] : features_.items()) {
          if (!features.contains(key) && got.rfind("fps ", 0) == 0) got = "no feature " + key;
        }
        throw core::InputError(
            "episode (task " + header.task + ", spec " + header.spec_hash + ")",
            fmt::format("the dataset's fps {}, robot {} and features (meta/info.json)", fps_, robot_),
            got);
      }
    }
    if (header.fps < 1) throw core::InputError("episode fps", "at least 1", std::to_string(header.fps));
  }

 public:
  void commit(std::unique_ptr<EpisodeSink> sink_in, const EpisodeOutcome& outcome) override {
    usable();
    HRIB_CHECK(opened_) << "commit of an episode begun by this writer";
    auto& sink = dynamic_cast<LeRobotSink&>(*sink_in);
    if (sink.rows == 0 || outcome.frames != sink.rows) {
      throw core::InputError(sink.where(),
                             fmt::format("an outcome of its {} frames (at least 1)", sink.rows),
                             fmt::format("{} frames", outcome.frames));
    }
    broken_ = true;  // until the commit has written what it must
    sink.finish_videos();
    EpisodeRecord record;
    record.index = static_cast<int64_t>(episodes_.size());
    record.length = sink.rows;
    record.instruction = sink.header.instruction;
    record.task = sink.header.task;
    record.task_id = sink.header.task_id;
    record.role = sink.header.role;
    record.spec_hash = sink.header.spec_hash;
    record.seed = sink.header.seed;
    record.variant = sink.header.variant;
    record.policy = sink.header.policy;
    record.action_space = sink.header.action_space;
    record.success = outcome.success;
    record.status = std::string(core::to_string(outcome.status));
    record.failure_labels = outcome.failure_labels;
    record.from_index = total_frames_;
    const ParquetTable table = frame_table(sink, record);
    for (const ParquetColumn& column : table.columns) record.stats[column.name] = column_stats(column);
    for (size_t c = 0; c < sink.header.cameras.size(); ++c) {
      record.stats[video_key(sink.header.cameras[c].name)] = sink.image_sums[c].stats();
    }
    if (version_ == LeRobotVersion::kV21) {
      write_table(episode_data_path(record.index), table);
      for (size_t c = 0; c < sink.video_paths.size(); ++c) {
        const fs::path target = dir_ / episode_video_path(record.index, sink.header.cameras[c].name);
        fs::create_directories(target.parent_path());
        fs::rename(sink.video_paths[c], target);
      }
      sink.placed = true;
      episodes_.push_back(std::move(record));
      total_frames_ += sink.rows;
      written_ = episodes_.size();
      write_meta();
    } else {
      std::vector<int64_t> video_bytes;
      bool full = !group_.episodes.empty() &&
                  group_.data_bytes + estimated_bytes(table) > options_.data_file_size_mb << 20;
      for (size_t c = 0; c < sink.video_paths.size(); ++c) {
        video_bytes.push_back(static_cast<int64_t>(fs::file_size(sink.video_paths[c])));
        full = full || (!group_.episodes.empty() &&
                        group_.video_bytes[c] + video_bytes[c] > options_.video_file_size_mb << 20);
      }
      // A full group closes when the next episode comes (or at finish), so a written group
      // holds only episodes the collector has recorded as committed (resume).
      if (full || static_cast<int64_t>(group_.episodes.size()) >= options_.episodes_per_file) close_group();
      if (!fs::exists(dir_ / "meta/info.json")) write_meta();  // the dataset exists from now on
      // The episode waits in DIR/.staging/ (its rows, mp4s and record, the record last) until
      // its group is written.
      write_table(staged_name(record.index, "parquet"), table);
      std::vector<fs::path> staged;
      for (size_t c = 0; c < sink.video_paths.size(); ++c) {
        staged.push_back(dir_ / staged_name(record.index, sink.header.cameras[c].name + ".mp4"));
        fs::rename(sink.video_paths[c], staged.back());
      }
      sink.placed = true;
      core::write_file_atomically(dir_ / staged_name(record.index, "json"),
                                  Json{{"episode", record_json(record)}, {"tasks", tasks_}}.dump() + "\n");
      add_to_group(record, table, staged);
      episodes_.push_back(std::move(record));
      total_frames_ += sink.rows;
    }
    broken_ = false;
  }

  void discard(std::unique_ptr<EpisodeSink> sink) override { sink.reset(); }

  void finish() override {
    usable();
    {
      std::lock_guard lock(mutex_);
      open_new();
    }
    broken_ = true;
    if (!group_.episodes.empty()) close_group();
    if (!features_.is_null()) write_meta();
    std::error_code ignored;
    fs::remove_all(staging(), ignored);
    broken_ = false;
  }

  // The written episodes of the dataset in `dir_` with their rows' vectors (no staged ones).
  std::vector<LeRobotEpisode> read_back() {
    if (!fs::exists(dir_ / "meta/info.json")) {
      throw core::InputError(dir_.string(), "a LeRobot dataset", "no meta/info.json");
    }
    load();
    std::vector<LeRobotEpisode> out;
    std::map<std::string, ParquetTable> files;
    for (size_t e = 0; e < written_; ++e) {
      const EpisodeRecord& r = episodes_[e];
      LeRobotEpisode episode;
      episode.index = r.index;
      episode.instruction = r.instruction;
      episode.task = r.task;
      episode.task_id = r.task_id;
      episode.role = r.role;
      episode.spec_hash = r.spec_hash;
      episode.variant = r.variant;
      episode.policy = r.policy;
      episode.action_space = r.action_space;
      episode.status = r.status;
      episode.seed = r.seed;
      episode.success = r.success;
      episode.failure_labels = r.failure_labels;
      const std::string relative = version_ == LeRobotVersion::kV21 ? episode_data_path(r.index) : group_data_path(r.group);
      auto it = files.find(relative);
      if (it == files.end()) it = files.emplace(relative, read_parquet(dir_ / relative)).first;
      const std::string where = (dir_ / relative).string();
      const ParquetTable& table = it->second;
      const std::vector<int64_t>& episode_index = column_of(table, "episode_index", where).int64s;
      const std::vector<int64_t>& index = column_of(table, "index", where).int64s;
      const ParquetColumn& state = column_of(table, kState, where);
      const ParquetColumn& action = column_of(table, kAction, where);
      const auto state_size = static_cast<size_t>(features_.at(kState).at("shape").at(0).get<int64_t>());
      const auto action_size = static_cast<size_t>(features_.at(kAction).at("shape").at(0).get<int64_t>());
      if (state.float32s.size() != index.size() * state_size || action.float32s.size() != index.size() * action_size) {
        throw core::InputError(where, "state and action vectors of the features' shapes", "others");
      }
      for (size_t row = 0; row < index.size(); ++row) {
        if (episode_index[row] != r.index) continue;
        if (index[row] != r.from_index + static_cast<int64_t>(episode.actions.size())) {
          throw core::InputError(where, fmt::format("row index {}", r.from_index + static_cast<int64_t>(episode.actions.size())),
                                 std::to_string(index[row]));
        }
        const auto at = [row](const ParquetColumn& column, size_t size) {
          return std::vector<float>(column.float32s.begin() + static_cast<std::ptrdiff_t>(row * size),
                                    column.float32s.begin() + static_cast<std::ptrdiff_t>((row + 1) * size));
        };
        episode.states.push_back(at(state, state_size));
        episode.actions.push_back(at(action, action_size));
      }
      if (static_cast<int64_t>(episode.actions.size()) != r.length) {
        throw core::InputError(where + ": episode " + std::to_string(r.index),
                               std::to_string(r.length) + " rows", std::to_string(episode.actions.size()));
      }
      out.push_back(std::move(episode));
    }
    return out;
  }

 private:
  struct FileGroup {  // v3.0: the open data parquet and mp4s
    ParquetTable table;
    int64_t data_bytes = 0;
    std::vector<int64_t> video_bytes;          // per camera
    std::vector<std::vector<fs::path>> segments;  // per camera, the episodes' staged mp4s
    std::vector<int64_t> episodes;             // their lengths
    int64_t frames = 0;
  };

  fs::path staging() const { return dir_ / ".staging"; }
  // v3.0: a committed episode's file in the staging folder until its group is written.
  static std::string staged_name(int64_t episode, const std::string& what) {
    return fmt::format(".staging/committed-{:06d}.{}", episode, what);
  }

  // The first use of a writer not resumed: the folder must not hold a dataset (mutex_ held).
  void open_new() {
    if (opened_) return;
    if (fs::exists(dir_ / "meta/info.json")) {
      throw core::InputError(dir_.string(), "a folder without a LeRobot dataset (or resume)",
                             "one (meta/info.json)");
    }
    opened_ = true;
    remove_unlisted_files();
  }

  void add_to_group(EpisodeRecord& record, const ParquetTable& table, const std::vector<fs::path>& staged) {
    record.group = group_number_;
    record.from_frame = group_.frames;
    append_rows(group_.table, table);
    group_.data_bytes += estimated_bytes(table);
    group_.video_bytes.resize(staged.size(), 0);
    group_.segments.resize(staged.size());
    for (size_t c = 0; c < staged.size(); ++c) {
      group_.segments[c].push_back(staged[c]);
      group_.video_bytes[c] += static_cast<int64_t>(fs::file_size(staged[c]));
    }
    group_.episodes.push_back(record.length);
    group_.frames += record.length;
  }

  // v3.0, resume: the open group again, of the staged episodes kept.
  void reload_group() {
    group_ = FileGroup{};
    const std::vector<std::string> cameras = cameras_of(features_);
    for (size_t e = written_; e < episodes_.size(); ++e) {
      const auto index = static_cast<int64_t>(e);
      std::vector<fs::path> staged;
      for (const std::string& camera : cameras) staged.push_back(dir_ / staged_name(index, camera + ".mp4"));
      add_to_group(episodes_[e], read_parquet(dir_ / staged_name(index, "parquet")), staged);
    }
  }

  // An episode's line of v2.1's episodes.jsonl with its stats (v3.0's staged record).
  Json record_json(const EpisodeRecord& r) const {
    return {{"episode_index", r.index},
            {"tasks", {r.instruction}},
            {"length", r.length},
            {"hribench", annotations_json(r)},
            {"stats", episode_stats_json(r)}};
  }

  EpisodeRecord record_from_json(const Json& line, const Json& stats, const std::string& where) const {
    EpisodeRecord r;
    r.index = static_cast<int64_t>(episodes_.size());
    if (core::json_member(line, "episode_index", where) != r.index) {
      throw core::InputError(where, "episode_index " + std::to_string(r.index), line.dump());
    }
    r.length = core::json_member(line, "length", where).get<int64_t>();
    r.instruction = core::json_member(line, "tasks", where).at(0).get<std::string>();
    read_annotations(core::json_member(line, "hribench", where), where, r);
    for (const auto& [key, value] : stats.items()) r.stats[key] = stats_from_json(value, where + " stats " + key);
    return r;
  }

  void usable() const {
    if (broken_) {
      throw core::InputError::Message(dir_.string(),
                                      "the dataset writer stopped at an earlier error; run again "
                                      "with --resume");
    }
  }

  // --- Paths (docs/datasets.md, LeRobot's utils.py).
  int64_t chunk_of(int64_t n) const { return n / options_.chunks_size; }
  std::string episode_data_path(int64_t episode) const {
    return fmt::format("data/chunk-{:03d}/episode_{:06d}.parquet", chunk_of(episode), episode);
  }
  std::string episode_video_path(int64_t episode, const std::string& camera) const {
    return fmt::format("videos/chunk-{:03d}/{}/episode_{:06d}.mp4", chunk_of(episode),
                       video_key(camera), episode);
  }
  std::string group_data_path(int64_t group) const {
    return fmt::format("data/chunk-{:03d}/file-{:03d}.parquet", chunk_of(group),
                       group % options_.chunks_size);
  }
  std::string group_video_path(int64_t group, const std::string& camera) const {
    return fmt::format("videos/{}/chunk-{:03d}/file-{:03d}.mp4", video_key(camera),
                       chunk_of(group), group % options_.chunks_size);
  }

  void write_table(const std::string& relative, const ParquetTable& table) const {
    fs::create_directories((dir_ / relative).parent_path());
    write_parquet(dir_ / relative, table);
  }

  // The rows of one episode (docs/datasets.md's columns). Registers its annotation texts.
  ParquetTable frame_table(const LeRobotSink& sink, const EpisodeRecord& record) {
    const int64_t n = sink.rows;
    ParquetTable table;
    ParquetColumn state = make_column(kState, ParquetType::kFloat32, true);
    state.float32s = sink.states;
    state.list_lengths.assign(static_cast<size_t>(n), static_cast<int64_t>(sink.header.state_names.size()));
    ParquetColumn action = make_column(kAction, ParquetType::kFloat32, true);
    action.float32s = sink.actions;
    action.list_lengths.assign(static_cast<size_t>(n), static_cast<int64_t>(sink.header.action_names.size()));
    ParquetColumn reward = make_column(kReward, ParquetType::kFloat32);
    reward.float32s = sink.rewards;
    ParquetColumn done = make_column(kDone, ParquetType::kBool);
    done.bools = sink.dones;
    ParquetColumn act = make_column(kHumanAct, ParquetType::kInt64);
    ParquetColumn events = make_column(kHumanEvents, ParquetType::kInt64);
    ParquetColumn timestamp = make_column("timestamp", ParquetType::kFloat32);
    ParquetColumn frame_index = make_column("frame_index", ParquetType::kInt64);
    ParquetColumn episode_index = make_column("episode_index", ParquetType::kInt64);
    ParquetColumn index = make_column("index", ParquetType::kInt64);
    ParquetColumn task_index = make_column("task_index", ParquetType::kInt64);
    const int64_t task = task_index_of(record.instruction);
    for (int64_t i = 0; i < n; ++i) {
      act.int64s.push_back(task_index_of(sink.acts[static_cast<size_t>(i)]));
      events.int64s.push_back(task_index_of(sink.events[static_cast<size_t>(i)]));
      timestamp.float32s.push_back(static_cast<float>(static_cast<double>(i) / fps_));
      frame_index.int64s.push_back(i);
      episode_index.int64s.push_back(record.index);
      index.int64s.push_back(record.from_index + i);
      task_index.int64s.push_back(task);
    }
    table.columns = {state,     action,      reward,        done,  act,       events,
                     timestamp, frame_index, episode_index, index, task_index};
    return table;
  }

  int64_t task_index_of(const std::string& text) {
    const auto [it, added] = task_index_.emplace(text, static_cast<int64_t>(tasks_.size()));
    if (added) tasks_.push_back(text);
    return it->second;
  }

  // v3.0: writes the open group's parquet and mp4s, then the meta files, and opens the next.
  void close_group() {
    write_table(group_data_path(group_number_), group_.table);
    const std::vector<std::string> cameras = cameras_of(features_);
    for (size_t c = 0; c < cameras.size(); ++c) {
      const fs::path target = dir_ / group_video_path(group_number_, cameras[c]);
      fs::create_directories(target.parent_path());
      concatenate_videos(group_.segments[c], group_.episodes, target, fps_);
    }
    const size_t first = written_;
    written_ = episodes_.size();
    write_meta();
    for (const auto& segments : group_.segments) {
      for (const fs::path& segment : segments) fs::remove(segment);
    }
    for (size_t e = first; e < written_; ++e) {
      fs::remove(dir_ / staged_name(static_cast<int64_t>(e), "parquet"));
      fs::remove(dir_ / staged_name(static_cast<int64_t>(e), "json"));
    }
    group_ = FileGroup{};
    ++group_number_;
  }

  // --- Meta files, each written atomically; info.json last.
  void write_meta() {
    fs::create_directories(dir_ / "meta");
    const auto write = [&](const std::string& name, const std::string& text) {
      core::write_file_atomically(dir_ / "meta" / name, text);
    };
    const auto written = static_cast<int64_t>(written_);
    int64_t frames = 0;
    for (size_t e = 0; e < written_; ++e) frames += episodes_[e].length;
    const std::vector<std::string> cameras = cameras_of(features_);
    Json info = {{"codebase_version", to_string(version_)},
                 {"robot_type", robot_},
                 {"total_episodes", written},
                 {"total_frames", frames},
                 {"total_tasks", tasks_.size()},
                 {"chunks_size", options_.chunks_size},
                 {"fps", fps_},
                 {"splits", {{"train", fmt::format("0:{}", written)}}},
                 {"features", features_}};
    if (version_ == LeRobotVersion::kV21) {
      std::string episodes_text, stats_text, tasks_text;
      for (size_t e = 0; e < written_; ++e) {
        const EpisodeRecord& r = episodes_[e];
        Json line = record_json(r);
        line.erase("stats");
        episodes_text += line.dump() + "\n";
        stats_text += Json{{"episode_index", r.index}, {"stats", episode_stats_json(r)}}.dump() + "\n";
      }
      for (size_t t = 0; t < tasks_.size(); ++t) {
        tasks_text += Json{{"task_index", t}, {"task", tasks_[t]}}.dump() + "\n";
      }
      write("episodes_stats.jsonl", stats_text);
      write("tasks.jsonl", tasks_text);
      write("episodes.jsonl", episodes_text);
      info["total_videos"] = written * static_cast<int64_t>(cameras.size());
      info["total_chunks"] = written == 0 ? 0 : chunk_of(written - 1) + 1;
      info["data_path"] = "data/chunk-{episode_chunk:03d}/episode_{episode_index:06d}.parquet";
      info["video_path"] = cameras.empty() ? Json(nullptr)
                                           : Json("videos/chunk-{episode_chunk:03d}/{video_key}/"
                                                  "episode_{episode_index:06d}.mp4");
    } else {
      write_table("meta/episodes/chunk-000/file-000.parquet", episodes_table(cameras));
      write_table("meta/tasks.parquet", tasks_table());
      info["data_files_size_in_mb"] = options_.data_file_size_mb;
      info["video_files_size_in_mb"] = options_.video_file_size_mb;
      info["data_path"] = "data/chunk-{chunk_index:03d}/file-{file_index:03d}.parquet";
      info["video_path"] = cameras.empty() ? Json(nullptr)
                                           : Json("videos/{video_key}/chunk-{chunk_index:03d}/"
                                                  "file-{file_index:03d}.mp4");
    }
    Json stats = Json::object();
    if (written_ > 0) {
      for (const auto& [key, ignored] : episodes_.front().stats) {
        std::vector<const FeatureStats*> parts;
        for (size_t e = 0; e < written_; ++e) parts.push_back(&episodes_[e].stats.at(key));
        stats[key] = stats_json(aggregate(parts), features_.at(key).at("dtype") == "video");
      }
    }
    write("stats.json", stats.dump(4) + "\n");
    write("modality.json", modality_of(features_).dump(4) + "\n");
    write("info.json", info.dump(4) + "\n");
  }

  Json episode_stats_json(const EpisodeRecord& r) const {
    Json stats = Json::object();
    for (const auto& [key, feature] : r.stats) {
      stats[key] = stats_json(feature, features_.at(key).at("dtype") == "video");
    }
    return stats;
  }

  // v3.0's meta/episodes table: one row per written episode.
  ParquetTable episodes_table(const std::vector<std::string>& cameras) const {
    std::vector<ParquetColumn> columns;
    const auto add = [&columns](ParquetColumn column) { columns.push_back(std::move(column)); };
    ParquetColumn episode_index = make_column("episode_index", ParquetType::kInt64);
    ParquetColumn tasks = make_column("tasks", ParquetType::kString, true);
    ParquetColumn length = make_column("length", ParquetType::kInt64);
    ParquetColumn data_chunk = make_column("data/chunk_index", ParquetType::kInt64);
    ParquetColumn data_file = make_column("data/file_index", ParquetType::kInt64);
    ParquetColumn from_index = make_column("dataset_from_index", ParquetType::kInt64);
    ParquetColumn to_index = make_column("dataset_to_index", ParquetType::kInt64);
    ParquetColumn meta_chunk = make_column("meta/episodes/chunk_index", ParquetType::kInt64);
    ParquetColumn meta_file = make_column("meta/episodes/file_index", ParquetType::kInt64);
    std::vector<std::array<ParquetColumn, 4>> videos;
    for (const std::string& camera : cameras) {
      const std::string prefix = "videos/" + video_key(camera) + "/";
      videos.push_back({make_column(prefix + "chunk_index", ParquetType::kInt64),
                        make_column(prefix + "file_index", ParquetType::kInt64),
                        make_column(prefix + "from_timestamp", ParquetType::kFloat64),
                        make_column(prefix + "to_timestamp", ParquetType::kFloat64)});
    }
    std::map<std::string, ParquetColumn> text;
    for (const char* key : {"task", "task_id", "role", "spec_hash", "policy", "action_space", "status"}) {
      text[key] = make_column(std::string("hribench/") + key, ParquetType::kString);
    }
    ParquetColumn seed = make_column("hribench/seed", ParquetType::kInt64);
    ParquetColumn variant = make_column("hribench/variant", ParquetType::kString);
    ParquetColumn success = make_column("hribench/success", ParquetType::kBool);
    ParquetColumn labels = make_column("hribench/failure_labels", ParquetType::kString, true);
    std::map<std::string, std::array<ParquetColumn, kStatCount + 1>> stats;  // and count
    for (size_t e = 0; e < written_; ++e) {
      const EpisodeRecord& r = episodes_[e];
      episode_index.int64s.push_back(r.index);
      tasks.strings.push_back(r.instruction);
      tasks.list_lengths.push_back(1);
      length.int64s.push_back(r.length);
      data_chunk.int64s.push_back(chunk_of(r.group));
      data_file.int64s.push_back(r.group % options_.chunks_size);
      from_index.int64s.push_back(r.from_index);
      to_index.int64s.push_back(r.from_index + r.length);
      meta_chunk.int64s.push_back(0);
      meta_file.int64s.push_back(0);
      for (auto& video : videos) {
        video[0].int64s.push_back(chunk_of(r.group));
        video[1].int64s.push_back(r.group % options_.chunks_size);
        video[2].float64s.push_back(static_cast<double>(r.from_frame) / fps_);
        video[3].float64s.push_back(static_cast<double>(r.from_frame + r.length) / fps_);
      }
      for (const auto& [key, value] : std::map<std::string, std::string>{
               {"task", r.task}, {"task_id", r.task_id}, {"role", r.role},
               {"spec_hash", r.spec_hash}, {"policy", r.policy},
               {"action_space", r.action_space}, {"status", r.status}}) {
        text[key].strings.push_back(value);
      }
      seed.int64s.push_back(static_cast<int64_t>(r.seed));  // the uint64's bits
      variant.strings.push_back(r.variant);
      success.bools.push_back(r.success);
      labels.strings.insert(labels.strings.end(), r.failure_labels.begin(), r.failure_labels.end());
      labels.list_lengths.push_back(static_cast<int64_t>(r.failure_labels.size()));
      for (const auto& [key, feature] : r.stats) {
        auto [it, added] = stats.try_emplace(key);
        if (added) {
          const std::string prefix = "stats/" + key + "/";
          for (size_t s = 0; s < kStatCount; ++s) {
            it->second[s] = make_column(prefix + kStatNames[s], ParquetType::kFloat64, true);
          }
          it->second[kStatCount] = make_column(prefix + "count", ParquetType::kInt64, true);
        }
        const auto values = feature.vectors();
        for (size_t s = 0; s < kStatCount; ++s) {
          it->second[s].float64s.insert(it->second[s].float64s.end(), values[s]->begin(), values[s]->end());
          it->second[s].list_lengths.push_back(static_cast<int64_t>(values[s]->size()));
        }
        it->second[kStatCount].int64s.push_back(feature.count);
        it->second[kStatCount].list_lengths.push_back(1);
      }
    }
    for (ParquetColumn* column : {&episode_index, &tasks, &length, &data_chunk, &data_file,
                                  &from_index, &to_index}) {
      add(std::move(*column));
    }
    for (auto& video : videos) {
      for (ParquetColumn& column : video) add(std::move(column));
    }
    add(std::move(meta_chunk));
    add(std::move(meta_file));
    for (auto& [key, column] : text) add(std::move(column));
    for (ParquetColumn* column : {&seed, &variant, &success, &labels}) add(std::move(*column));
    for (auto& [key, five] : stats) {
      for (ParquetColumn& column : five) add(std::move(column));
    }
    ParquetTable table;
    table.columns = std::move(columns);
    return table;
  }

  // v3.0's meta/tasks.parquet: task_index, and the task text as the pandas index (LeRobot's
  // load_tasks reads it through pandas, which restores the index from this metadata).
  ParquetTable tasks_table() const {
    ParquetTable table;
    ParquetColumn index = make_column("task_index", ParquetType::kInt64);
    ParquetColumn task = make_column("task", ParquetType::kString);
    for (size_t t = 0; t < tasks_.size(); ++t) {
      index.int64s.push_back(static_cast<int64_t>(t));
      task.strings.push_back(tasks_[t]);
    }
    table.columns = {index, task};
    const Json pandas = {
        {"index_columns", {"task"}},
        {"column_indexes",
         {{{"name", nullptr}, {"field_name", nullptr}, {"pandas_type", "unicode"},
           {"numpy_type", "object"}, {"metadata", {{"encoding", "UTF-8"}}}}}},
        {"columns",
         {{{"name", "task_index"}, {"field_name", "task_index"}, {"pandas_type", "int64"},
           {"numpy_type", "int64"}, {"metadata", nullptr}},
          {{"name", "task"}, {"field_name", "task"}, {"pandas_type", "unicode"},
           {"numpy_type", "object"}, {"metadata", nullptr}}}},
        {"creator", {{"library", "hribench"}, {"version", "1"}}},
        {"pandas_version", "1.5.3"}};
    table.metadata = {{"pandas", pandas.dump()}};
    return table;
  }

  // --- Resume.
  void load() {
    const std::string info_path = (dir_ / "meta/info.json").string();
    const Json info = core::read_json_file(info_path);
    const auto expect = [&](const char* key, const Json& value) {
      const Json& got = core::json_member(info, key, info_path);
      if (got != value) throw core::InputError(info_path + ": " + key, value.dump(), got.dump());
    };
    expect("codebase_version", to_string(version_));
    expect("chunks_size", options_.chunks_size);
    if (version_ == LeRobotVersion::kV30) {
      expect("data_files_size_in_mb", options_.data_file_size_mb);
      expect("video_files_size_in_mb", options_.video_file_size_mb);
    }
    features_ = core::json_member(info, "features", info_path);
    fps_ = core::json_member(info, "fps", info_path).get<int>();
    robot_ = core::json_string(core::json_member(info, "robot_type", info_path), info_path + ": robot_type");
    if (version_ == LeRobotVersion::kV21) {
      load_v21();
    } else {
      load_v30();
    }
    written_ = episodes_.size();
    if (version_ == LeRobotVersion::kV30) load_staged();
  }

  // v3.0: the committed episodes waiting in the staging folder, in order, each complete (its
  // record, written last, present).
  void load_staged() {
    int64_t rows = 0;
    for (const EpisodeRecord& r : episodes_) rows += r.length;
    while (true) {
      const auto index = static_cast<int64_t>(episodes_.size());
      const fs::path record_path = dir_ / staged_name(index, "json");
      if (!fs::exists(record_path)) break;
      const Json staged = core::read_json_file(record_path.string());
      const std::string where = record_path.string();
      EpisodeRecord r = record_from_json(core::json_member(staged, "episode", where),
                                         core::json_member(core::json_member(staged, "episode", where), "stats", where),
                                         where);
      for (const Json& task : core::json_member(staged, "tasks", where)) task_index_of(task.get<std::string>());
      r.from_index = rows;
      rows += r.length;
      episodes_.push_back(std::move(r));
    }
    reload_group();
  }

  std::vector<Json> read_lines(const std::string& name) const {
    const std::string path = (dir_ / "meta" / name).string();
    std::ifstream in(path);
    if (!in) throw core::InputError::Message(path, "cannot open the file");
    std::vector<Json> lines;
    std::string line;
    for (size_t n = 1; std::getline(in, line); ++n) {
      if (!line.empty()) lines.push_back(core::parse_json(line, path, n));
    }
    return lines;
  }

  void load_v21() {
    for (const Json& task : read_lines("tasks.jsonl")) {
      task_index_of(core::json_string(core::json_member(task, "task", "tasks.jsonl"), "tasks.jsonl"));
    }
    const std::vector<Json> stats = read_lines("episodes_stats.jsonl");
    int64_t rows = 0;
    for (const Json& line : read_lines("episodes.jsonl")) {
      const std::string where = fmt::format("meta/episodes.jsonl episode {}", episodes_.size());
      if (stats.size() <= episodes_.size()) throw core::InputError(where, "its stats", "none");
      EpisodeRecord r = record_from_json(line, core::json_member(stats[episodes_.size()], "stats", where), where);
      r.from_index = rows;
      rows += r.length;
      episodes_.push_back(std::move(r));
    }
  }

  void load_v30() {
    const fs::path tasks_path = dir_ / "meta/tasks.parquet";
    const ParquetTable tasks = read_parquet(tasks_path);
    for (const std::string& task : column_of(tasks, "task", tasks_path.string()).strings) task_index_of(task);
    const fs::path episodes_path = dir_ / "meta/episodes/chunk-000/file-000.parquet";
    if (!fs::exists(episodes_path)) return;
    const ParquetTable table = read_parquet(episodes_path);
    const std::string where = episodes_path.string();
    const auto ints = [&](const std::string& name) { return column_of(table, name, where).int64s; };
    const auto texts = [&](const std::string& name) { return column_of(table, name, where).strings; };
    const std::vector<int64_t> length = ints("length"), chunk = ints("data/chunk_index"),
                               file = ints("data/file_index"), from = ints("dataset_from_index"),
                               seed = ints("hribench/seed");
    const std::vector<std::string> tasks_of = texts("tasks"), task = texts("hribench/task"),
                                   task_id = texts("hribench/task_id"), role = texts("hribench/role"),
                                   spec = texts("hribench/spec_hash"), policy = texts("hribench/policy"),
                                   space = texts("hribench/action_space"), status = texts("hribench/status"),
                                   variant = texts("hribench/variant");
    const std::vector<bool> success = column_of(table, "hribench/success", where).bools;
    const ParquetColumn& labels = column_of(table, "hribench/failure_labels", where);
    const std::vector<std::string> cameras = cameras_of(features_);
    const std::vector<double> from_timestamp =
        cameras.empty() ? std::vector<double>(length.size(), 0.0)
                        : column_of(table, "videos/" + video_key(cameras.front()) + "/from_timestamp", where).float64s;
    size_t label = 0;
    for (size_t e = 0; e < length.size(); ++e) {
      EpisodeRecord r;
      r.index = static_cast<int64_t>(e);
      r.length = length[e];
      r.instruction = tasks_of[e];
      r.task = task[e];
      r.task_id = task_id[e];
      r.role = role[e];
      r.spec_hash = spec[e];
      r.policy = policy[e];
      r.action_space = space[e];
      r.status = status[e];
      r.seed = static_cast<uint64_t>(seed[e]);
      r.variant = variant[e];
      r.success = success[e];
      for (int64_t k = 0; k < labels.list_lengths[e]; ++k) r.failure_labels.push_back(labels.strings[label++]);
      r.group = chunk[e] * options_.chunks_size + file[e];
      r.from_index = from[e];
      r.from_frame = std::llround(from_timestamp[e] * fps_);
      episodes_.push_back(std::move(r));
      group_number_ = std::max(group_number_, episodes_.back().group + 1);
    }
    for (const auto& [key, feature] : features_.items()) {
      const std::string prefix = "stats/" + key + "/";
      if (table.find(prefix + "count") == nullptr) continue;
      std::array<const ParquetColumn*, kStatCount> values{};
      for (size_t s = 0; s < kStatCount; ++s) values[s] = &column_of(table, prefix + kStatNames[s], where);
      const std::vector<int64_t> counts = ints(prefix + "count");
      std::array<size_t, kStatCount> at{};
      for (size_t e = 0; e < episodes_.size(); ++e) {
        FeatureStats stats;
        const auto out = stats.vectors();
        for (size_t s = 0; s < kStatCount; ++s) {
          const auto n = static_cast<size_t>(values[s]->list_lengths[e]);
          out[s]->assign(values[s]->float64s.begin() + static_cast<std::ptrdiff_t>(at[s]),
                         values[s]->float64s.begin() + static_cast<std::ptrdiff_t>(at[s] + n));
          at[s] += n;
        }
        stats.count = counts[e];
        episodes_[e].stats[key] = std::move(stats);
      }
    }
  }

  // Removes the files of data/ and videos/ that the meta files do not list, and the staging
  // folder: what a run stopped between a file and its meta left.
  void remove_unlisted_files() {
    std::set<fs::path> listed;
    const std::vector<std::string> cameras = features_.is_null() ? std::vector<std::string>{} : cameras_of(features_);
    for (size_t e = 0; e < episodes_.size(); ++e) {
      const EpisodeRecord& r = episodes_[e];
      if (version_ == LeRobotVersion::kV21) {
        listed.insert(dir_ / episode_data_path(r.index));
        for (const std::string& camera : cameras) listed.insert(dir_ / episode_video_path(r.index, camera));
      } else if (e < written_) {
        listed.insert(dir_ / group_data_path(r.group));
        for (const std::string& camera : cameras) listed.insert(dir_ / group_video_path(r.group, camera));
      } else {  // staged
        for (const std::string& what : {std::string("parquet"), std::string("json")}) {
          listed.insert(dir_ / staged_name(r.index, what));
        }
        for (const std::string& camera : cameras) listed.insert(dir_ / staged_name(r.index, camera + ".mp4"));
      }
    }
    for (const char* folder : {"data", "videos", ".staging"}) {
      if (!fs::exists(dir_ / folder)) continue;
      std::vector<fs::path> unlisted;
      for (const auto& entry : fs::recursive_directory_iterator(dir_ / folder)) {
        if (entry.is_regular_file() && listed.count(entry.path()) == 0) unlisted.push_back(entry.path());
      }
      for (const fs::path& path : unlisted) fs::remove(path);
    }
  }

  const fs::path dir_;
  const LeRobotVersion version_;
  const LeRobotOptions options_;
  std::mutex mutex_;  // features_, fps_, robot_ while episodes begin on worker threads
  Json features_;     // null until the first episode (or the resumed dataset's)
  int fps_ = 0;
  std::string robot_;
  std::atomic<int64_t> next_sink_{0};
  std::vector<std::string> tasks_;
  std::map<std::string, int64_t> task_index_;
  std::vector<EpisodeRecord> episodes_;  // committed, in order
  size_t written_ = 0;                   // of them, those on disk and in the meta files
  int64_t total_frames_ = 0;             // rows of all committed episodes
  int64_t group_number_ = 0;  // v3.0: the open group's number
  FileGroup group_;
  bool broken_ = false;
  bool opened_ = false;  // resume() ran, or a first episode found the folder without a dataset
};

}  // namespace

std::string_view to_string(LeRobotVersion version) {
  return version == LeRobotVersion::kV21 ? "v2.1" : "v3.0";
}

std::vector<LeRobotEpisode> read_lerobot_episodes(const std::filesystem::path& dir) {
  const std::string info_path = (dir / "meta/info.json").string();
  if (!fs::exists(info_path)) throw core::InputError(dir.string(), "a LeRobot dataset", "no meta/info.json");
  const Json info = core::read_json_file(info_path);
  const std::string version =
      core::json_string(core::json_member(info, "codebase_version", info_path), info_path + ": codebase_version");
  if (version != "v2.1" && version != "v3.0") {
    throw core::InputError(info_path + ": codebase_version", "\"v2.1\" or \"v3.0\"", "\"" + version + "\"");
  }
  LeRobotOptions options;
  options.chunks_size = core::json_member(info, "chunks_size", info_path).get<int64_t>();
  if (version == "v3.0") {
    options.data_file_size_mb = core::json_member(info, "data_files_size_in_mb", info_path).get<int64_t>();
    options.video_file_size_mb = core::json_member(info, "video_files_size_in_mb", info_path).get<int64_t>();
  }
  return LeRobotWriter(dir, version == "v2.1" ? LeRobotVersion::kV21 : LeRobotVersion::kV30, options).read_back();
}

std::unique_ptr<DatasetWriter> make_lerobot_writer(const std::filesystem::path& dir,
                                                   LeRobotVersion version,
                                                   const LeRobotOptions& options) {
  return std::make_unique<LeRobotWriter>(dir, version, options);
}

}  // namespace hribench::io
