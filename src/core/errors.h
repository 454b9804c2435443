#pragma once
// The three tiers of trouble in HRIBench (docs/design.md), all in this one header.
//
// 1. Programmer bug: HRIB_CHECK(cond) << "context"; — always on (also in release builds),
//    prints file:line, the failed condition and the context, then aborts.
// 2. Bad user input (YAML, motion file, CLI flag, a malformed reply from a remote policy):
//    throw InputError{where, expected, got}. `where` is file:line:col or a key path. The CLI
//    turns it into one line and a non-zero exit; nothing written before is lost.
// 3. Trouble inside one episode (MuJoCo warning, NaN action, policy gone): never thrown past
//    the episode. It is counted in the episode's Data/log and the episode gets an
//    EpisodeStatus other than kOk, with a reason; the run goes on with the next episode.

#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace hribench::core {

// Tier 2. what() is "WHERE: expected EXPECTED, got GOT" (or "WHERE: MESSAGE").
class InputError : public std::runtime_error {
 public:
  InputError(std::string where, std::string expected, std::string got);
  // A problem that is not naturally "expected X, got Y" (e.g. "cannot open file").
  static InputError Message(std::string where, std::string message);

  const std::string& where() const { return where_; }
  const std::string& expected() const { return expected_; }
  const std::string& got() const { return got_; }

 private:
  InputError(std::string where, std::string expected, std::string got, std::string what);
  std::string where_;
  std::string expected_;
  std::string got_;
};

// Tier 3: how an episode ended, from the run's point of view.
enum class EpisodeStatus {
  kOk,           // ran to the end; metrics are meaningful
  kInvalid,      // the simulation became unusable (MuJoCo instability warning, NaN state)
  kPolicyError,  // the policy failed (wrong shape, NaN/out-of-range action, server gone)
};
std::string_view to_string(EpisodeStatus status);

namespace internal {
// Collects the context streamed into a failed check, then aborts in its destructor.
class CheckFailure {
 public:
  CheckFailure(const char* file, int line, const char* condition);
  [[noreturn]] ~CheckFailure();
  CheckFailure(const CheckFailure&) = delete;
  CheckFailure& operator=(const CheckFailure&) = delete;
  template <typename T>
  CheckFailure& operator<<(const T& value) {
    stream_ << value;
    return *this;
  }

 private:
  std::ostringstream stream_;
};
}  // namespace internal

}  // namespace hribench::core

// Tier 1: always-on invariant check. Usage: HRIB_CHECK(n > 0) << "n=" << n;
#define HRIB_CHECK(condition)                                              \
  if (condition) {                                                         \
  } else /* NOLINT */                                                      \
    ::hribench::core::internal::CheckFailure(__FILE__, __LINE__, #condition)
