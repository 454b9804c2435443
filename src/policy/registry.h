#pragma once
// Policies by name, so the runner and the CLI never know the concrete classes. A policy
// reference is either `NAME` or `NAME?key=value&key=value` (e.g. "random?seed=3&space=joint_pos")
// or `SCHEME://ADDRESS[?options]` (e.g. "openpi://localhost:8000"): the scheme is the name.
//
// The built-ins (noop, random) are registered on first use. Later layers register their own
// with register_policy() (static registration objects in a static library would be dropped by
// the linker, so registration is an explicit call).

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "policy/policy.h"

namespace hribench::policy {

// A parsed policy reference.
struct PolicyRef {
  std::string name;                           // "noop", "random", "openpi", ...
  std::string address;                        // after "://" (empty for plain names)
  std::map<std::string, std::string> options; // from "?k=v&k=v"; take_* erases what it reads
  std::vector<std::string> known;             // every key take_* was asked for (for messages)
};

// Throws core::InputError (where = "policy") for an empty name or a malformed option.
PolicyRef parse_policy_ref(std::string_view text);

// Reads option `key` (erasing it from the map) or returns `fallback`; throws core::InputError
// if the value is not of the type asked for.
std::string take_option(PolicyRef& ref, const std::string& key, const std::string& fallback);
double take_option(PolicyRef& ref, const std::string& key, double fallback);  // finite only
// An integer option in [min, max], parsed exactly (decimal digits only: no sign, fraction,
// exponent, hex, nan or inf); anything else throws core::InputError naming the range.
uint64_t take_integer_option(PolicyRef& ref, const std::string& key, uint64_t fallback,
                             uint64_t min, uint64_t max);
// Throws core::InputError naming the first option left in `ref` (an unknown option) and the
// options the policy knows (those its factory asked for).
void reject_unknown_options(const PolicyRef& ref);

using PolicyFactory = std::function<std::unique_ptr<Policy>(PolicyRef ref)>;

struct PolicyEntry {
  std::string name;
  std::string help;
  PolicyFactory make;
};

// Adds (or replaces) a factory under `name`.
void register_policy(PolicyEntry entry);
// The registered names, sorted.
std::vector<std::string> policy_names();
// Builds a policy from a reference; throws core::InputError for an unknown name (listing the
// known ones) or bad options.
std::unique_ptr<Policy> make_policy(std::string_view reference);

}  // namespace hribench::policy
