#include "policy/registry.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fmt/format.h>
#include <mutex>
#include <system_error>

#include "core/errors.h"
#include "policy/builtin.h"
#include "policy/oracle.h"

namespace hribench::policy {
namespace {

constexpr uint64_t kMaxChunk = 100000;  // actions per chunk a built-in policy may be asked for

std::map<std::string, PolicyEntry> make_builtins() {
  std::map<std::string, PolicyEntry> entries;
  entries["noop"] = PolicyEntry{
      "noop",
      "holds the robot still (options: space=ee_delta|joint_pos, cameras=NAME:WxH+NAME:WxH)",
      [](PolicyRef ref) {
        const ActionSpace space = action_space_from_string(
            take_option(ref, "space", "ee_delta"), "policy noop: space");
        std::vector<CameraRequest> cameras =
            parse_camera_requests(take_option(ref, "cameras", ""), "policy noop: cameras");
        reject_unknown_options(ref);
        return std::unique_ptr<Policy>(new NoopPolicy(space, std::move(cameras)));
      }};
  entries["random"] = PolicyEntry{
      "random",
      "uniform random actions (options: seed=INT, scale=(0,1], chunk=INT, "
      "space=ee_delta|joint_pos, cameras=NAME:WxH+NAME:WxH)",
      [](PolicyRef ref) {
        const ActionSpace space = action_space_from_string(
            take_option(ref, "space", "ee_delta"), "policy random: space");
        const uint64_t seed = take_integer_option(ref, "seed", 0, 0, UINT64_MAX);
        const double scale = take_option(ref, "scale", 1.0);
        const uint64_t chunk = take_integer_option(ref, "chunk", 1, 1, kMaxChunk);
        std::vector<CameraRequest> cameras =
            parse_camera_requests(take_option(ref, "cameras", ""), "policy random: cameras");
        reject_unknown_options(ref);
        return std::unique_ptr<Policy>(new RandomPolicy(space, seed, scale, ActionLimits{},
                                                        static_cast<int>(chunk), std::move(cameras)));
      }};
  // The privileged expert and its scripted baselines (policy/oracle.h).
  const auto expert = [&entries](Competence competence, const char* help) {
    const std::string name(to_string(competence));
    entries[name] = PolicyEntry{name, help, [competence](PolicyRef ref) {
                                  reject_unknown_options(ref);
                                  return make_expert(competence);
                                }};
  };
  expert(Competence::kOracle,
         "privileged expert: waits for cues, keeps the separation, re-plans, obeys contradictions");
  expert(Competence::kReactive,
         "the oracle without safety and recovery: no separation monitoring, no re-plan, "
         "ignores contradictions, never stands down");
  expert(Competence::kBlind, "reactive that also ignores cues and timing: starts at t = 0");
  return entries;
}

struct Registry {
  std::mutex mutex;
  std::map<std::string, PolicyEntry> entries = make_builtins();
};

Registry& registry() {
  static Registry r;
  return r;
}

}  // namespace

PolicyRef parse_policy_ref(std::string_view text) {
  PolicyRef ref;
  std::string_view rest = text;
  const size_t q = rest.find('?');
  const std::string_view head = rest.substr(0, q);
  const size_t scheme_end = head.find("://");
  if (scheme_end != std::string_view::npos) {
    ref.name = std::string(head.substr(0, scheme_end));
    ref.address = std::string(head.substr(scheme_end + 3));
  } else {
    ref.name = std::string(head);
  }
  if (ref.name.empty()) {
    throw core::InputError("policy", "a policy name (e.g. noop, random)", "'" + std::string(text) + "'");
  }
  if (q == std::string_view::npos) return ref;
  // Options: k=v pairs separated by '&'.
  std::string_view options = rest.substr(q + 1);
  while (!options.empty()) {
    const size_t amp = options.find('&');
    const std::string_view pair = options.substr(0, amp);
    const size_t eq = pair.find('=');
    if (eq == std::string_view::npos || eq == 0) {
      throw core::InputError("policy " + ref.name, "options as key=value",
                             "'" + std::string(pair) + "'");
    }
    ref.options[std::string(pair.substr(0, eq))] = std::string(pair.substr(eq + 1));
    options = amp == std::string_view::npos ? std::string_view() : options.substr(amp + 1);
  }
  return ref;
}

std::string take_option(PolicyRef& ref, const std::string& key, const std::string& fallback) {
  ref.known.push_back(key);
  const auto it = ref.options.find(key);
  if (it == ref.options.end()) return fallback;
  std::string value = it->second;
  ref.options.erase(it);
  return value;
}

double take_option(PolicyRef& ref, const std::string& key, double fallback) {
  ref.known.push_back(key);
  const auto it = ref.options.find(key);
  if (it == ref.options.end()) return fallback;
  const std::string value = it->second;
  ref.options.erase(it);
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(number)) {
    throw core::InputError("policy " + ref.name + ": " + key, "a finite number", "'" + value + "'");
  }
  return number;
}

uint64_t take_integer_option(PolicyRef& ref, const std::string& key, uint64_t fallback,
                             uint64_t min, uint64_t max) {
  ref.known.push_back(key);
  const auto it = ref.options.find(key);
  if (it == ref.options.end()) return fallback;
  const std::string value = it->second;
  ref.options.erase(it);
  // Exactly the decimal digits of an integer in range, nothing before or after.
  uint64_t number = 0;
  const char* first = value.data();
  const char* last = value.data() + value.size();
  const auto [ptr, ec] = std::from_chars(first, last, number);
  if (ec != std::errc() || ptr != last || number < min ||
      number > max) {
    throw core::InputError("policy " + ref.name + ": " + key,
                           fmt::format("an integer in [{}, {}]", min, max), "'" + value + "'");
  }
  return number;
}

void reject_unknown_options(const PolicyRef& ref) {
  if (ref.options.empty()) return;
  std::string known;
  for (const std::string& key : ref.known) known += (known.empty() ? "" : ", ") + key;
  throw core::InputError("policy " + ref.name, known.empty() ? "no options" : "one of the options " + known,
                         "'" + ref.options.begin()->first + "'");
}

void register_policy(PolicyEntry entry) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::string name = entry.name;
  r.entries[name] = std::move(entry);
}

std::vector<std::string> policy_names() {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::vector<std::string> names;
  for (const auto& [name, entry] : r.entries) names.push_back(name);
  return names;
}

std::unique_ptr<Policy> make_policy(std::string_view reference) {
  PolicyRef ref = parse_policy_ref(reference);
  PolicyFactory factory;
  {
    Registry& r = registry();
    std::lock_guard lock(r.mutex);
    const auto it = r.entries.find(ref.name);
    if (it != r.entries.end()) factory = it->second.make;
  }
  if (!factory) {
    std::string known;
    for (const std::string& name : policy_names()) known += (known.empty() ? "" : ", ") + name;
    throw core::InputError("policy", "one of " + known, "'" + ref.name + "'");
  }
  return factory(std::move(ref));
}

}  // namespace hribench::policy
