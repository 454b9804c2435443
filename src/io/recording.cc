#include "io/recording.h"

#include <string>
#include <vector>

#include "core/json.h"

namespace hribench::io {

void DatasetWriter::resume(const std::vector<EpisodeHeader>& committed) {
  if (!committed.empty()) {
    throw core::InputError("--resume", "a dataset format that can be continued",
                           std::to_string(committed.size()) + " committed episodes of a format that cannot");
  }
}

void DatasetWriter::store(std::unique_ptr<EpisodeSink>, const std::filesystem::path&) {
  throw core::InputError("--shard", "a dataset format whose episodes can be stored apart", "one that cannot");
}

std::unique_ptr<EpisodeSink> DatasetWriter::load(const std::filesystem::path&) {
  throw core::InputError("--shard", "a dataset format whose episodes can be stored apart", "one that cannot");
}

nlohmann::json episode_header_json(const EpisodeHeader& h) {
  nlohmann::json cameras = nlohmann::json::array();
  for (const CameraSpec& c : h.cameras) cameras.push_back({{"name", c.name}, {"width", c.width}, {"height", c.height}});
  return {{"task", h.task},
          {"task_id", h.task_id},
          {"role", h.role},
          {"instruction", h.instruction},
          {"spec_hash", h.spec_hash},
          {"seed", h.seed},
          {"variant", h.variant},
          {"policy", h.policy},
          {"robot", h.robot},
          {"fps", h.fps},
          {"state_names", h.state_names},
          {"action_names", h.action_names},
          {"action_space", h.action_space},
          {"cameras", cameras},
          {"action_low", h.action_low},
          {"action_high", h.action_high},
          {"max_frames", h.max_frames}};
}

EpisodeHeader episode_header_from_json(const nlohmann::json& json, const std::string& where) {
  EpisodeHeader h;
  try {
    const auto text = [&](const char* key) { return core::json_string(core::json_member(json, key, where), where + "." + key); };
    h.task = text("task");
    h.task_id = text("task_id");
    h.role = text("role");
    h.instruction = text("instruction");
    h.spec_hash = text("spec_hash");
    h.seed = json.at("seed").get<uint64_t>();
    h.variant = text("variant");
    h.policy = text("policy");
    h.robot = text("robot");
    h.fps = json.at("fps").get<int>();
    h.state_names = json.at("state_names").get<std::vector<std::string>>();
    h.action_names = json.at("action_names").get<std::vector<std::string>>();
    h.action_space = text("action_space");
    for (const nlohmann::json& c : json.at("cameras")) {
      h.cameras.push_back({c.at("name").get<std::string>(), c.at("width").get<int>(), c.at("height").get<int>()});
    }
    h.action_low = json.at("action_low").get<std::vector<float>>();
    h.action_high = json.at("action_high").get<std::vector<float>>();
    h.max_frames = json.at("max_frames").get<int64_t>();
  } catch (const nlohmann::json::exception& e) {
    throw core::InputError(where, "an episode header (docs/datasets.md)", e.what());
  }
  return h;
}

}  // namespace hribench::io
