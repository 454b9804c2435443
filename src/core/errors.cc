#include "core/errors.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <utility>

namespace hribench::core {

InputError::InputError(std::string where, std::string expected, std::string got)
    : InputError(where, expected, got,
                 where + ": expected " + expected + ", got " + got) {}

InputError::InputError(std::string where, std::string expected, std::string got,
                       std::string what)
    : std::runtime_error(std::move(what)),
      where_(std::move(where)),
      expected_(std::move(expected)),
      got_(std::move(got)) {}

InputError InputError::Message(std::string where, std::string message) {
  std::string what = where + ": " + message;
  return InputError(std::move(where), "", std::move(message), std::move(what));
}

std::string_view to_string(EpisodeStatus status) {
  switch (status) {
    case EpisodeStatus::kOk:
      return "ok";
    case EpisodeStatus::kInvalid:
      return "invalid";
    case EpisodeStatus::kPolicyError:
      return "policy_error";
  }
  return "unknown";
}

EpisodeStatus episode_status_from_string(const std::string& name, const std::string& where) {
  for (const auto status : {EpisodeStatus::kOk, EpisodeStatus::kInvalid, EpisodeStatus::kPolicyError}) {
    if (to_string(status) == name) return status;
  }
  throw InputError(where, "ok, invalid or policy_error", "'" + name + "'");
}

namespace {
std::atomic<bool> check_failure_throws{false};
}  // namespace

void set_check_failure_throws(bool throws) { check_failure_throws.store(throws); }

namespace internal {

CheckFailure::CheckFailure(const char* file, int line, const char* condition) {
  stream_ << file << ":" << line << ": check failed: " << condition << " ";
}

CheckFailure::~CheckFailure() noexcept(false) {
  if (check_failure_throws.load()) throw CheckError(stream_.str());
  std::fprintf(stderr, "%s\n", stream_.str().c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace internal
}  // namespace hribench::core
