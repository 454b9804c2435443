// The openpi client against the reference server (tests/remote/servers/openpi_server.py): a
// query round trip with two 224x224 images, the chunk length read from the reply, replies
// decoded by their dtype, and every fault the server can be told to make ending the query with
// a one-line PolicyError, after which the next episode connects again.

#include "remote/openpi.h"

#include <gtest/gtest.h>

#include <chrono>
#include <string>

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

std::unique_ptr<policy::Policy> client(int port, const std::string& options = "") {
  register_remote_policies();
  return policy::make_policy("openpi://127.0.0.1:" + std::to_string(port) + (options.empty() ? "" : "?" + options));
}

TEST(OpenpiClient, QueriesTheReferenceServerWithTwoImages) {
  ServerProcess server(reference_server("openpi_server.py", {"--horizon", "10", "--dtype", "<f2"}));
  auto p = client(server.port());
  const policy::PolicySpec spec = p->spec();
  ASSERT_EQ(spec.cameras.size(), 2u);
  EXPECT_EQ(spec.cameras[0].width, 224);
  p->reset(policy::EpisodeInfo{});
  for (int i = 0; i < 3; ++i) {
    const policy::ActionChunk chunk = p->act(observation(spec));
    ASSERT_EQ(chunk.actions.size(), 10u);  // read from the reply
    ASSERT_EQ(chunk.actions[0].size(), 7u);
    EXPECT_EQ(chunk.actions[0][6], 1.0);  // decoded from float16
    EXPECT_EQ(chunk.actions[0][0], 0.0);
  }
}

TEST(OpenpiClient, StockPresetsSendTheKeysTheStockConfigsRead) {
  // The reference server checks pi05_libero's and pi05_droid's keys and shapes and answers
  // (10, 7) and (15, 8) chunks.
  for (const std::string preset : {"libero", "droid"}) {
    ServerProcess server(reference_server("openpi_server.py", {"--preset", preset}));
    auto p = client(server.port(), "preset=" + preset);
    p->reset(policy::EpisodeInfo{});
    const policy::ActionChunk chunk = p->act(observation(p->spec()));
    EXPECT_EQ(chunk.actions.size(), preset == "libero" ? 10u : 15u) << preset;
    EXPECT_EQ(validation_error(chunk, p->spec()), "(no error)") << preset;
    EXPECT_EQ(chunk.actions[0].back(), 1.0) << preset;  // open
  }
}

TEST(OpenpiClient, ReplanEveryAndWhileThinkingComeFromTheReference) {
  ServerProcess server(reference_server("openpi_server.py", {}));
  EXPECT_FALSE(client(server.port())->spec().execute_while_thinking);
  const policy::PolicySpec spec = client(server.port(), "replan_every=4&while_thinking=continue")->spec();
  EXPECT_EQ(spec.replan_every, 4);
  EXPECT_TRUE(spec.execute_while_thinking);
  const std::string message = ::hribench::testing::error_of([&] { client(server.port(), "while_thinking=run"); });
  EXPECT_NE(message.find("hold or continue"), std::string::npos) << message;
}

TEST(OpenpiClient, NothingListeningIsOneInputErrorAtOnce) {
  int port = 0;
  {
    ServerProcess server(reference_server("openpi_server.py", {}));
    port = server.port();
  }
  const auto start = std::chrono::steady_clock::now();
  const std::string message = ::hribench::testing::error_of([&] { client(port); });
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(6));
  EXPECT_NE(message.find("GET /healthz"), std::string::npos) << message;
  EXPECT_NE(message.find("refused"), std::string::npos) << message;
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
}

struct Fault {
  std::string mode;
  std::string expected;  // in the PolicyError message
};

class OpenpiFault : public ::testing::TestWithParam<Fault> {};

TEST_P(OpenpiFault, EndsTheQueryWithOneLineThenTheNextEpisodeReconnects) {
  // The fault from the second request of each connection on: the first query works.
  ServerProcess server(reference_server("openpi_server.py", {"--mode", GetParam().mode, "--after", "2"}));
  auto p = client(server.port(), "timeout=0.5");
  for (int episode = 0; episode < 2; ++episode) {
    p->reset(policy::EpisodeInfo{});
    EXPECT_EQ(p->act(observation(p->spec())).actions.size(), 10u) << "episode " << episode;
    std::string message = "(no error)";
    const auto start = std::chrono::steady_clock::now();
    try {
      p->act(observation(p->spec()));
    } catch (const policy::PolicyError& e) {
      message = e.what();
    }
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(3));
    EXPECT_NE(message.find(GetParam().expected), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_FALSE(is_connect_failure(message)) << message;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Modes, OpenpiFault,
    ::testing::Values(Fault{"close", "failed: openpi://127.0.0.1:"},
                      Fault{"close", "the server closed the connection (code 1000)"},
                      Fault{"hang", "no reply within 500 ms"},
                      Fault{"garbage", "reply: not msgpack"},
                      Fault{"wrong_keys", "no 'actions' in the reply (got: action;"},
                      Fault{"wrong_shape", "actions: expected shape (H, 7), got (10, 5)"},
                      Fault{"error", "server error (close 1011): RuntimeError: policy exploded on purpose"}),
    [](const ::testing::TestParamInfo<Fault>& param) { return param.param.mode + std::to_string(param.index); });

TEST(OpenpiClient, NanAndOutOfRangeRepliesAreLeftToTheRunnersValidation) {
  for (const std::string mode : {"nan", "range"}) {
    ServerProcess server(reference_server("openpi_server.py", {"--mode", mode}));
    auto p = client(server.port());
    p->reset(policy::EpisodeInfo{});
    const policy::ActionChunk chunk = p->act(observation(p->spec()));
    const std::string message = validation_error(chunk, p->spec());
    EXPECT_NE(message.find(mode == "nan" ? "non_finite" : "out_of_range"), std::string::npos) << message;
  }
}

TEST(OpenpiClient, ADeadServerIsAConnectFailureOfTheNextEpisode) {
  ServerProcess server(reference_server("openpi_server.py", {"--mode", "die", "--after", "2"}));
  auto p = client(server.port(), "timeout=1");
  p->reset(policy::EpisodeInfo{});
  p->act(observation(p->spec()));
  EXPECT_THROW(p->act(observation(p->spec())), policy::PolicyError);  // the server exits
  std::string message = "(no error)";
  try {
    p->reset(policy::EpisodeInfo{});
  } catch (const policy::PolicyError& e) {
    message = e.what();
  }
  EXPECT_TRUE(is_connect_failure(message)) << message;
  EXPECT_NE(message.find("refused"), std::string::npos) << message;
}

TEST(OpenpiClient, BadReferencesAreInputErrors) {
  register_remote_policies();
  using ::hribench::testing::error_of;
  EXPECT_NE(error_of([] { policy::make_policy("openpi://localhost"); }).find("HOST:PORT"), std::string::npos);
  EXPECT_NE(error_of([] { policy::make_policy("openpi://localhost:99999"); }).find("1..65535"), std::string::npos);
  EXPECT_NE(error_of([] { policy::make_policy("openpi://localhost:8000?timeout=-1"); }).find("timeout"),
            std::string::npos);
  EXPECT_NE(error_of([] { policy::make_policy("openpi://localhost:8000?colour=red"); }).find("colour"),
            std::string::npos);
}

}  // namespace
}  // namespace hribench::remote
