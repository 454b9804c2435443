#pragma once
// The three tiers of trouble in HRIBench (docs/design.md), all in this one header.
//
// 1. Programmer bug: HRIB_CHECK(cond) << "context"; — always on (also in release builds),
//    prints file:line, the failed condition and the context, then aborts — or, in a process
//    that asked for it (the Python module, docs/python.md), throws CheckError instead.
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
// The status `to_string` names; throws InputError (where = `where`) for another name.
EpisodeStatus episode_status_from_string(const std::string& name, const std::string& where);

// Tier 1 in a host that must not die (the Python module): what a failed check throws when
// set_check_failure_throws(true). what() is the message a failed check prints.
class CheckError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};
// Process-wide: false (the default) prints and aborts; true throws CheckError. A check that
// fails inside a noexcept function still ends the process (std::terminate).
void set_check_failure_throws(bool throws);

namespace internal {
// Collects the context streamed into a failed check, then aborts (or throws CheckError) in its
// destructor.
class CheckFailure {
 public:
  CheckFailure(const char* file, int line, const char* condition);
  [[noreturn]] ~CheckFailure() noexcept(false);
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
