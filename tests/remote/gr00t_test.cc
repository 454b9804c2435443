// The GR00T client against the reference server (tests/remote/servers/gr00t_server.py) in both
// eras: the N1.5 flat and N1.6 nested layouts, the (16,) squeezed groups, float32 state as N1.6
// asserts, the api token, and every fault ending the query with a one-line PolicyError; after
// a timeout the REQ socket is made anew, so the late reply is never taken for the next one.

#include "remote/gr00t.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>
#include <thread>

#include "policy/registry.h"
#include "remote/remote.h"
#include "remote/remote_test_support.h"
#include "support/server_process.h"
#include "support/test_files.h"

namespace hribench::remote {
namespace {

using ::hribench::testing::reference_server;
using ::hribench::testing::ServerProcess;

using testing::observation;
using testing::validation_error;

std::unique_ptr<policy::Policy> client(int port, const std::string& options) {
  register_remote_policies();
  return policy::make_policy("gr00t://127.0.0.1:" + std::to_string(port) + "?" + options);
}

std::string act_error(policy::Policy& p) {
  try {
    p.act(observation(p.spec()));
  } catch (const policy::PolicyError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Gr00tClient, BothErasGiveTheSixteenStepChunk) {
  for (const std::string era : {"n15", "n16"}) {
    ServerProcess server(reference_server("gr00t_server.py", {"--era", era}));
    auto p = client(server.port(), "era=" + era);
    p->reset(policy::EpisodeInfo{});
    const policy::ActionChunk chunk = p->act(observation(p->spec()));
    ASSERT_EQ(chunk.actions.size(), 16u) << era;
    EXPECT_EQ(chunk.actions[3], (policy::Action{0, 0, 0, 0, 0, 0, 1})) << era;
  }
}

TEST(Gr00tClient, TheApiTokenIsSentAndABadOneIsRefused) {
  ServerProcess server(reference_server("gr00t_server.py", {"--token", "secret"}));
  auto p = client(server.port(), "api_token=secret");
  p->reset(policy::EpisodeInfo{});
  EXPECT_EQ(p->act(observation(p->spec())).actions.size(), 16u);
  const std::string message = ::hribench::testing::error_of([&] { client(server.port(), "api_token=wrong"); });
  EXPECT_NE(message.find("Unauthorized: Invalid API token"), std::string::npos) << message;
}

TEST(Gr00tClient, NothingListeningIsOneInputErrorAtOnce) {
  int port = 0;
  { port = ServerProcess(reference_server("gr00t_server.py", {})).port(); }
  const auto start = std::chrono::steady_clock::now();
  const std::string message = ::hribench::testing::error_of([&] { client(port, "timeout=1"); });
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(3));
  EXPECT_NE(message.find("no reply to ping within 1000 ms"), std::string::npos) << message;
}

TEST(Gr00tClient, AfterATimeoutTheSocketIsNewAndTheLateReplyIsDropped) {
  ServerProcess server(reference_server("gr00t_server.py", {"--mode", "slow", "--after", "2", "--once", "--delay", "1"}));
  auto p = client(server.port(), "timeout=0.4&era=n16");
  p->reset(policy::EpisodeInfo{});
  EXPECT_EQ(p->act(observation(p->spec())).actions.size(), 16u);
  const auto start = std::chrono::steady_clock::now();
  const std::string message = act_error(*p);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_NE(message.find("failed: gr00t://127.0.0.1:"), std::string::npos) << message;
  EXPECT_NE(message.find("no reply to get_action within 400 ms"), std::string::npos) << message;
  // The next episode pings on a new socket once the server has sent its late reply (to the old
  // socket, which is gone): the answers are the ping's and this query's, not the late one.
  std::this_thread::sleep_for(std::chrono::milliseconds(900));
  p->reset(policy::EpisodeInfo{});
  EXPECT_EQ(p->act(observation(p->spec())).actions.size(), 16u);
}

struct Fault {
  std::string mode;
  std::string era;
  std::string expected;
};

class Gr00tFault : public ::testing::TestWithParam<Fault> {};

TEST_P(Gr00tFault, EndsTheQueryWithOneLine) {
  ServerProcess server(reference_server("gr00t_server.py", {"--mode", GetParam().mode, "--era", GetParam().era}));
  auto p = client(server.port(), "timeout=1&era=" + GetParam().era);
  p->reset(policy::EpisodeInfo{});
  const std::string message = act_error(*p);
  EXPECT_NE(message.find(GetParam().expected), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

INSTANTIATE_TEST_SUITE_P(
    Modes, Gr00tFault,
    ::testing::Values(Fault{"garbage", "n16", "reply: not msgpack"},
                      Fault{"wrong_keys", "n16", "no 'actions' in the reply (got: arm;"},
                      Fault{"wrong_keys", "n15", "no 'actions' in the reply (got: arm;"},
                      Fault{"wrong_shape", "n16", "action 'eef_delta': expected 6 values per step, got 4"},
                      Fault{"error", "n16", "server error: policy exploded on purpose"},
                      Fault{"raw_error", "n15", "server error: ERROR"}),
    [](const ::testing::TestParamInfo<Fault>& param) { return param.param.mode + "_" + param.param.era; });

TEST(Gr00tClient, NanAndOutOfRangeRepliesAreLeftToTheRunnersValidation) {
  for (const std::string mode : {"nan", "range"}) {
    ServerProcess server(reference_server("gr00t_server.py", {"--mode", mode, "--era", "n15"}));
    auto p = client(server.port(), "era=n15");
    p->reset(policy::EpisodeInfo{});
    const policy::ActionChunk chunk = p->act(observation(p->spec()));
    const std::string message = validation_error(chunk, p->spec());
    EXPECT_NE(message.find(mode == "nan" ? "non_finite" : "out_of_range"), std::string::npos) << message;
  }
}

TEST(Gr00tClient, ADeadServerIsAConnectFailureOfTheNextEpisode) {
  ServerProcess server(reference_server("gr00t_server.py", {"--mode", "die", "--after", "2"}));
  auto p = client(server.port(), "timeout=0.5");
  p->reset(policy::EpisodeInfo{});
  p->act(observation(p->spec()));
  EXPECT_NE(act_error(*p).find("no reply to get_action within 500 ms"), std::string::npos);
  std::string message = "(no error)";
  try {
    p->reset(policy::EpisodeInfo{});
  } catch (const policy::PolicyError& e) {
    message = e.what();
  }
  EXPECT_TRUE(is_connect_failure(message)) << message;
}

TEST(Gr00tClient, BadOptionsAreInputErrors) {
  register_remote_policies();
  const std::string message = ::hribench::testing::error_of([] { policy::make_policy("gr00t://localhost:5555?era=n2"); });
  EXPECT_NE(message.find("n15 or n16"), std::string::npos) << message;
}

}  // namespace
}  // namespace hribench::remote
