#include "remote/gr00t.h"

#include <fmt/format.h>
#include <zmq.hpp>

#include "core/errors.h"
#include "remote/remote.h"

namespace hribench::remote {
namespace {

using policy::PolicyError;
using policy::PolicyErrorKind;

constexpr std::string_view kLanguageN15 = "annotation.human.task_description";
constexpr std::string_view kSideChannelN15 = "hribench.";

// `a` with `n` leading dimensions of size 1 added (the batch and time axes GR00T expects).
NdArray with_leading_ones(NdArray a, size_t n) {
  a.shape.insert(a.shape.begin(), n, 1);
  return a;
}

// `a` without leading dimensions of size 1 beyond `keep` dimensions.
NdArray without_leading_ones(NdArray a, size_t keep) {
  while (a.shape.size() > keep && a.shape.front() == 1) a.shape.erase(a.shape.begin());
  return a;
}

NdArray flat(NdArray a) {
  a.shape = {a.size()};
  return a;
}

}  // namespace

struct Gr00tPolicy::Socket {
  zmq::context_t context{1};
  std::unique_ptr<zmq::socket_t> req;
};

Value gr00t_request(ObservationGroups g, Gr00tEra era) {
  if (era == Gr00tEra::kN15) {
    Map data;
    for (auto& [name, a] : g.video) data.emplace_back("video." + name, with_leading_ones(std::move(a), 1));
    for (auto& [name, a] : g.state) data.emplace_back("state." + name, with_leading_ones(std::move(a), 1));
    data.emplace_back(std::string(kLanguageN15), List{std::move(g.language)});
    for (auto& [name, v] : g.extras) data.emplace_back(std::string(kSideChannelN15) + name, std::move(v));
    return data;
  }
  Map video;
  Map state;
  for (auto& [name, a] : g.video) video.emplace_back(name, with_leading_ones(std::move(a), 2));
  for (auto& [name, a] : g.state) state.emplace_back(name, with_leading_ones(std::move(a), 2));
  Map observation{{"video", std::move(video)},
                  {"state", std::move(state)},
                  {"language", Map{{"task", List{List{std::move(g.language)}}}}}};
  Value options;
  if (!g.extras.empty()) options = Map{{"hribench", std::move(g.extras)}};
  return Map{{"observation", std::move(observation)}, {"options", std::move(options)}};
}

ObservationGroups gr00t_groups(const Map& data) {
  ObservationGroups g;
  if (const Value* observation = find(data, "observation")) {
    const Map& o = observation->map("observation");
    for (const auto& [name, v] : at(o, "video", "observation").map("observation.video")) {
      g.video.emplace_back(name, without_leading_ones(v.array("video." + name), 3));
    }
    for (const auto& [name, v] : at(o, "state", "observation").map("observation.state")) {
      g.state.emplace_back(name, flat(v.array("state." + name)));
    }
    const Value& task = at(at(o, "language", "observation").map("observation.language"), "task", "language");
    const List& batch = task.list("language.task");
    if (batch.empty() || batch[0].list("language.task[0]").empty()) throw WireError("language.task: empty");
    g.language = batch[0].list("language.task[0]")[0].str("language.task[0][0]");
    if (const Value* options = find(data, "options"); options != nullptr && !options->is_nil()) {
      if (const Value* extras = find(options->map("options"), "hribench")) g.extras = extras->map("options.hribench");
    }
    return g;
  }
  for (const auto& [key, v] : data) {
    if (key.starts_with("video.")) {
      g.video.emplace_back(key.substr(6), without_leading_ones(v.array(key), 3));
    } else if (key.starts_with("state.")) {
      g.state.emplace_back(key.substr(6), flat(v.array(key)));
    } else if (key == kLanguageN15) {
      const List& l = v.list(key);
      if (l.empty()) throw WireError(std::string(kLanguageN15) + ": empty");
      g.language = l[0].str(key);
    } else if (key.starts_with(kSideChannelN15)) {
      g.extras.emplace_back(key.substr(kSideChannelN15.size()), v);
    }
  }
  return g;
}

ActionGroups gr00t_actions(const Value& reply) {
  ActionGroups groups;
  if (const auto* list = std::get_if<List>(&reply.v)) {  // N1.6: [action, info]
    if (list->empty()) throw WireError("reply: an empty list (N1.6 answers [action, info])");
    for (const auto& [name, v] : (*list)[0].map("reply[0] (the action dict)")) {
      NdArray a = v.array("action " + name);
      if (a.shape.size() == 3 && a.shape[0] == 1) a.shape.erase(a.shape.begin());  // batch of 1
      groups.emplace_back(name, std::move(a));
    }
    return groups;
  }
  for (const auto& [key, v] : reply.map("reply")) {
    if (key.starts_with("action.")) groups.emplace_back(key.substr(7), v.array(key));
  }
  return groups;
}

Value gr00t_reply(const ActionGroups& groups, Gr00tEra era) {
  Map actions;
  for (const auto& [name, a] : groups) {
    if (era == Gr00tEra::kN15) {
      // N1.5 squeezes its outputs: a 1-D group comes back as (H,).
      NdArray squeezed = a;
      if (squeezed.shape.size() == 2 && squeezed.shape[1] == 1) squeezed.shape.pop_back();
      actions.emplace_back("action." + name, std::move(squeezed));
    } else {
      actions.emplace_back(name, with_leading_ones(a, 1));
    }
  }
  if (era == Gr00tEra::kN15) return actions;
  return List{std::move(actions), Map{}};
}

Gr00tPolicy::Gr00tPolicy(Endpoint endpoint, Gr00tEra era, std::string api_token)
    : endpoint_(std::move(endpoint)), era_(era), api_token_(std::move(api_token)), socket_(std::make_unique<Socket>()) {
  const std::string where = "policy " + endpoint_.text();
  Value config;
  try {
    const Value pong = call("ping", nullptr, endpoint_.connect_timeout);
    (void)pong;
    config = call("get_modality_config", nullptr, endpoint_.connect_timeout);
  } catch (const TransportError& e) {
    throw core::InputError(where, "a GR00T policy server there (an answer to ping)", e.what());
  } catch (const std::exception& e) {
    throw core::InputError(where, "a GR00T policy server there (ping and get_modality_config)", e.what());
  }
  if (const auto* m = std::get_if<Map>(&config.v)) {
    if (const Value* spec = find(*m, "hribench/spec")) {
      try {
        endpoint_.preset.served_spec = spec_from_value(*spec, "modality config hribench/spec");
      } catch (const WireError& e) {
        throw core::InputError(where, "a valid hribench/spec in the modality config", e.what());
      }
    }
  }
  preset_ = make_preset(endpoint_.preset, where + ": preset");
  spec_ = preset_->spec();
  if (endpoint_.replan_every) spec_.replan_every = *endpoint_.replan_every;
  spec_.execute_while_thinking = endpoint_.execute_while_thinking;
}

Gr00tPolicy::~Gr00tPolicy() = default;

Value Gr00tPolicy::call(const std::string& name, const Value* data, std::chrono::milliseconds timeout) {
  if (!socket_->req) {
    socket_->req = std::make_unique<zmq::socket_t>(socket_->context, zmq::socket_type::req);
    socket_->req->set(zmq::sockopt::linger, 0);
    socket_->req->connect(fmt::format("tcp://{}:{}", endpoint_.host, endpoint_.port));
  }
  Map envelope{{"endpoint", name}};
  if (data != nullptr) envelope.emplace_back("data", *data);
  if (!api_token_.empty()) envelope.emplace_back("api_token", api_token_);
  const std::string request = pack(envelope, ArrayCodec::kGr00t);
  zmq::socket_t& req = *socket_->req;
  req.set(zmq::sockopt::sndtimeo, static_cast<int>(timeout.count()));
  req.set(zmq::sockopt::rcvtimeo, static_cast<int>(timeout.count()));
  zmq::message_t reply;
  try {
    if (!req.send(zmq::buffer(request), zmq::send_flags::none) || !req.recv(reply, zmq::recv_flags::none)) {
      socket_->req.reset();  // lock-step: a REQ socket without its reply cannot send again
      throw TransportError(fmt::format("no reply to {} within {} ms", name, timeout.count()), false);
    }
  } catch (const zmq::error_t& e) {
    socket_->req.reset();
    throw TransportError(fmt::format("{}: {}", name, e.what()), false);
  }
  const std::string_view bytes(static_cast<const char*>(reply.data()), reply.size());
  if (bytes == "ERROR") throw PolicyError(PolicyErrorKind::kFailed, endpoint_.text() + ": server error: ERROR");
  Value value = unpack(bytes);
  if (const auto* m = std::get_if<Map>(&value.v)) {
    if (const Value* error = find(*m, "error")) {
      throw PolicyError(PolicyErrorKind::kFailed, fmt::format("{}: server error: {}", endpoint_.text(),
                                                              error->kind() == "str" ? error->str("error") : "(not text)"));
    }
  }
  return value;
}

void Gr00tPolicy::reset(const policy::EpisodeInfo& info) {
  preset_->begin(info);
  if (!socket_->req) {
    // After a fault: is anyone there? ZeroMQ connects lazily, so a ping tells a server that is
    // gone (a connection failure, which the run counts) from one that failed once.
    try {
      call("ping", nullptr, endpoint_.connect_timeout);
    } catch (const TransportError& e) {
      throw transport_failure(endpoint_, TransportError(e.what(), true));
    } catch (const WireError& e) {
      throw PolicyError(PolicyErrorKind::kFailed, endpoint_.text() + ": ping: " + e.what());
    }
  }
  if (era_ != Gr00tEra::kN16) return;
  try {
    const Value options;
    const Value data = Map{{"options", options}};
    call("reset", &data, endpoint_.timeout);
  } catch (const TransportError& e) {
    throw transport_failure(endpoint_, e);
  } catch (const WireError& e) {
    throw PolicyError(PolicyErrorKind::kFailed, endpoint_.text() + ": reset: " + e.what());
  }
}

policy::ActionChunk Gr00tPolicy::act(const policy::Observation& observation) {
  try {
    const Value data = gr00t_request(preset_->encode(observation), era_);
    return preset_->decode(gr00t_actions(call("get_action", &data, endpoint_.timeout)));
  } catch (const TransportError& e) {
    throw transport_failure(endpoint_, e);
  } catch (const WireError& e) {
    const bool garbage = std::string_view(e.what()).starts_with("not msgpack");
    throw PolicyError(garbage ? PolicyErrorKind::kFailed : PolicyErrorKind::kWrongShape,
                      endpoint_.text() + ": reply: " + e.what());
  }
}

}  // namespace hribench::remote
