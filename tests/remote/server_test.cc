// Our openpi server (remote/server.h) with our client: the health check, the metadata frame
// declaring the served policy's spec, one chunk per request, and an error frame + close 1011
// for a request that starts no episode.

#include "remote/server.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <future>
#include <thread>

#include "policy/builtin.h"
#include "remote/openpi.h"
#include "remote/websocket.h"

namespace hribench::remote {
namespace {

class ServedNoop : public ::testing::Test {
 protected:
  void SetUp() override {
    std::promise<uint16_t> bound;
    thread_ = std::thread([this, &bound] {
      serve_openpi("127.0.0.1", 0, [] { return std::make_unique<policy::NoopPolicy>(); },
                   [&bound](uint16_t port) { bound.set_value(port); }, stop_);
    });
    port_ = std::to_string(bound.get_future().get());
  }
  void TearDown() override {
    stop_ = true;
    thread_.join();
  }
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::string port_;
};

TEST_F(ServedNoop, AnswersHealthChecksAndDeclaresItsSpec) {
  std::string body;
  EXPECT_EQ(http_get("127.0.0.1", port_, "/healthz", std::chrono::seconds(2), body), 200);
  EXPECT_EQ(body, "OK\n");
  Endpoint endpoint;
  endpoint.scheme = "openpi";
  endpoint.host = "127.0.0.1";
  endpoint.port = port_;
  OpenpiPolicy client(endpoint);
  EXPECT_TRUE(client.spec().cameras.empty());  // noop's spec, from the metadata frame
  EXPECT_EQ(client.spec().action_space, policy::ActionSpace::kEeDelta);
  client.reset(policy::EpisodeInfo{});
  policy::Observation obs;
  obs.proprio.joint_pos = model::JointVector(7, 0.0);
  obs.proprio.joint_vel = model::JointVector(7, 0.0);
  obs.proprio.gripper_width = 0.04;
  const policy::ActionChunk chunk = client.act(obs);
  ASSERT_EQ(chunk.actions.size(), 1u);
  EXPECT_EQ(chunk.actions[0], (policy::Action{0, 0, 0, 0, 0, 0, 0.5}));  // 0.04 m of the Panda's 0.08
}

TEST_F(ServedNoop, ARequestWithoutAnEpisodeIsAnErrorFrameThenClose1011) {
  WebSocketClient ws("127.0.0.1", port_, std::chrono::seconds(2));
  ws.read(std::chrono::seconds(2));  // metadata
  ObservationGroups groups;
  groups.language = "x";
  ws.write_binary(pack(openpi_request(groups), ArrayCodec::kOpenpi), std::chrono::seconds(2));
  const WebSocketClient::Frame frame = ws.read(std::chrono::seconds(2));
  EXPECT_TRUE(frame.text);
  EXPECT_NE(frame.data.find("Traceback"), std::string::npos) << frame.data;
  EXPECT_NE(frame.data.find("no state 'joint_position'"), std::string::npos) << frame.data;
  EXPECT_EQ(ws.read_close(std::chrono::seconds(2)), 1011);
}

}  // namespace
}  // namespace hribench::remote
