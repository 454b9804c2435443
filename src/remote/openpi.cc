#include "remote/openpi.h"

#include <algorithm>

#include <fmt/format.h>

#include "core/errors.h"
#include "remote/remote.h"

namespace hribench::remote {
namespace {

using policy::PolicyError;
using policy::PolicyErrorKind;

constexpr std::string_view kObservation = "observation/";
constexpr std::string_view kSideChannel = "hribench/";

// The last non-empty line of a Python traceback: the exception and its message.
std::string last_line(const std::string& text) {
  size_t end = text.size();
  while (end > 0) {
    while (end > 0 && (text[end - 1] == '\n' || text[end - 1] == '\r' || text[end - 1] == ' ')) --end;
    const size_t begin = text.rfind('\n', end == 0 ? 0 : end - 1);
    const size_t from = begin == std::string::npos ? 0 : begin + 1;
    if (end > from) return text.substr(from, end - from);
    end = from;
  }
  return "(empty error text)";
}

}  // namespace

std::string Endpoint::text() const { return scheme + "://" + host + ":" + port; }

Endpoint endpoint_from_ref(policy::PolicyRef& ref, const std::string& default_dtype) {
  Endpoint e;
  e.scheme = ref.name;
  const std::string where = "policy " + ref.name + "://" + ref.address;
  const size_t colon = ref.address.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == ref.address.size()) {
    throw core::InputError(where, "HOST:PORT", "'" + ref.address + "'");
  }
  e.host = ref.address.substr(0, colon);
  e.port = ref.address.substr(colon + 1);
  if (!std::all_of(e.port.begin(), e.port.end(), [](char c) { return c >= '0' && c <= '9'; }) ||
      e.port.size() > 5 || std::stoi(e.port) == 0 || std::stoi(e.port) > 65535) {
    throw core::InputError(where, "a port in 1..65535", "'" + e.port + "'");
  }
  const double timeout = policy::take_option(ref, "timeout", 120.0);
  if (!(timeout > 0) || timeout > 3600) throw core::InputError(where + ": timeout", "seconds in (0, 3600]", std::to_string(timeout));
  e.timeout = std::chrono::milliseconds(static_cast<int64_t>(timeout * 1000));
  e.connect_timeout = std::min(e.timeout, std::chrono::milliseconds(5000));
  if (ref.options.count("replan_every") != 0) {
    e.replan_every = static_cast<int>(policy::take_integer_option(ref, "replan_every", 1, 1, 10000));
  }
  const std::string while_thinking = policy::take_option(ref, "while_thinking", "hold");
  if (while_thinking != "hold" && while_thinking != "continue") {
    throw core::InputError(where + ": while_thinking", "hold or continue", "'" + while_thinking + "'");
  }
  e.execute_while_thinking = while_thinking == "continue";
  e.preset.name = policy::take_option(ref, "preset", "hribench");
  const std::string dtype = policy::take_option(ref, "dtype", default_dtype);
  if (dtype != "f8" && dtype != "f4") throw core::InputError(where + ": dtype", "f8 or f4", "'" + dtype + "'");
  e.preset.state_dtype = "<" + dtype;
  e.preset.space = policy::action_space_from_string(policy::take_option(ref, "space", "ee_delta"), where + ": space");
  e.preset.allow_privileged = policy::take_integer_option(ref, "privileged", 0, 0, 1) == 1;
  return e;
}

policy::PolicyError transport_failure(const Endpoint& endpoint, const TransportError& error) {
  if (error.connect_failure()) {
    return PolicyError(PolicyErrorKind::kFailed, std::string(kCannotConnect) + endpoint.text() + ": " + error.what());
  }
  return PolicyError(PolicyErrorKind::kFailed, endpoint.text() + ": " + error.what());
}

Map openpi_request(ObservationGroups groups) {
  Map request;
  request.reserve(groups.video.size() + groups.state.size() + groups.extras.size() + 1);
  for (auto& [name, array] : groups.video) request.emplace_back(std::string(kObservation) + name, std::move(array));
  for (auto& [name, array] : groups.state) request.emplace_back(std::string(kObservation) + name, std::move(array));
  request.emplace_back("prompt", std::move(groups.language));
  for (auto& [name, value] : groups.extras) request.emplace_back(std::string(kSideChannel) + name, std::move(value));
  return request;
}

ObservationGroups openpi_groups(const Map& request) {
  ObservationGroups g;
  for (const auto& [key, value] : request) {
    if (key.starts_with(kObservation)) {
      const std::string name = key.substr(kObservation.size());
      const NdArray& a = value.array(key);
      (a.dtype == "|u1" && a.shape.size() == 3 ? g.video : g.state).emplace_back(name, a);
    } else if (key.starts_with(kSideChannel)) {
      g.extras.emplace_back(key.substr(kSideChannel.size()), value);
    } else if (key == "prompt") {
      g.language = value.str("prompt");
    }
  }
  return g;
}

OpenpiPolicy::OpenpiPolicy(Endpoint endpoint) : endpoint_(std::move(endpoint)) {
  const std::string where = "policy " + endpoint_.text();
  std::string body;
  int status = 0;
  try {
    status = http_get(endpoint_.host, endpoint_.port, "/healthz", endpoint_.connect_timeout, body);
  } catch (const TransportError& e) {
    throw core::InputError(where, "an openpi policy server there (GET /healthz)", e.what());
  }
  if (status != 200) {
    throw core::InputError(where, "an openpi policy server there (GET /healthz answers 200)",
                           fmt::format("status {}", status));
  }
  try {
    connect();
  } catch (const std::exception& e) {
    throw core::InputError(where, "an openpi policy server there (metadata frame after the upgrade)", e.what());
  }
  if (const Value* spec = find(metadata_, "hribench/spec")) {
    try {
      endpoint_.preset.served_spec = spec_from_value(*spec, "metadata hribench/spec");
    } catch (const WireError& e) {
      throw core::InputError(where, "a valid hribench/spec in the server's metadata", e.what());
    }
  }
  preset_ = make_preset(endpoint_.preset, where + ": preset");
  spec_ = preset_->spec();
  if (endpoint_.replan_every) spec_.replan_every = *endpoint_.replan_every;
  spec_.execute_while_thinking = endpoint_.execute_while_thinking;
}

void OpenpiPolicy::connect() {
  ws_.reset();
  auto ws = std::make_unique<WebSocketClient>(endpoint_.host, endpoint_.port, endpoint_.connect_timeout);
  const WebSocketClient::Frame frame = ws->read(endpoint_.connect_timeout);
  if (frame.text) throw WireError("the server's first frame is text, not the metadata: " + last_line(frame.data));
  const Value metadata = unpack(frame.data);
  metadata_ = metadata.map("metadata");
  ws_ = std::move(ws);
}

void OpenpiPolicy::reset(const policy::EpisodeInfo& info) {
  if (!ws_) {
    try {
      connect();
    } catch (const TransportError& e) {
      throw transport_failure(endpoint_, e);
    } catch (const WireError& e) {
      throw PolicyError(PolicyErrorKind::kFailed, endpoint_.text() + ": metadata: " + e.what());
    }
  }
  preset_->begin(info);
}

policy::ActionChunk OpenpiPolicy::act(const policy::Observation& observation) {
  HRIB_CHECK(ws_ != nullptr) << "act() before reset()";
  try {
    ws_->write_binary(pack(openpi_request(preset_->encode(observation)), ArrayCodec::kOpenpi), endpoint_.timeout);
    const WebSocketClient::Frame frame = ws_->read(endpoint_.timeout);
    if (frame.text) {
      const int code = ws_->read_close(endpoint_.connect_timeout);
      ws_.reset();
      throw PolicyError(PolicyErrorKind::kFailed,
                        fmt::format("{}: server error{}: {}", endpoint_.text(),
                                    code != 0 ? fmt::format(" (close {})", code) : "", last_line(frame.data)));
    }
    const Value reply = unpack(frame.data);
    ActionGroups groups;
    for (const auto& [key, value] : reply.map("reply")) {
      if (const auto* array = std::get_if<NdArray>(&value.v)) groups.emplace_back(key, *array);
    }
    return preset_->decode(groups);
  } catch (const TransportError& e) {
    ws_.reset();
    throw transport_failure(endpoint_, e);
  } catch (const WireError& e) {
    ws_.reset();
    const bool garbage = std::string_view(e.what()).starts_with("not msgpack");
    throw PolicyError(garbage ? PolicyErrorKind::kFailed : PolicyErrorKind::kWrongShape,
                      endpoint_.text() + ": reply: " + e.what());
  } catch (const PolicyError&) {
    ws_.reset();
    throw;
  }
}

}  // namespace hribench::remote
