// The presets: the hribench layout carries an observation (state track, privileged episode and
// events included) bit for bit through either protocol's layout and msgpack; libero and droid
// map our observations and their actions as docs/remote-policies.md says.

#include "remote/preset.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "remote/gr00t.h"
#include "remote/openpi.h"
#include "remote/remote_test_support.h"
#include "script/check.h"
#include "script/sample.h"
#include "script/scenario.h"
#include "support/test_files.h"

namespace hribench::remote {
namespace {

policy::Observation rich_observation(const policy::PolicySpec& spec) {
  policy::Observation obs = testing::observation(spec);
  obs.time = 1.0 / 3.0;
  obs.proprio.joint_pos[2] = std::nextafter(obs.proprio.joint_pos[2], 1.0);
  obs.proprio.X_WT.translation = core::Vec3(0.3, -0.2, 0.9);
  obs.proprio.X_WT.rotation = core::Quat(Eigen::AngleAxisd(M_PI / 2, core::Vec3::UnitZ()));
  policy::StateObservation state;
  state.human_joints_W[4] = core::Vec3(1.0 / 7.0, 2, 3);
  state.objects.push_back({"cup", obs.proprio.X_WT});
  obs.state = state;
  obs.events.push_back({0.5, "cue", "offer.go", "go"});
  return obs;
}

policy::PolicySpec rich_spec() {
  policy::PolicySpec spec;
  spec.cameras = {{"agentview", 8, 6}};
  spec.state_track = true;
  spec.privileged = true;
  return spec;
}

void expect_same(const policy::Observation& a, const policy::Observation& b) {
  EXPECT_EQ(a.time, b.time);
  EXPECT_EQ(a.instruction, b.instruction);
  EXPECT_TRUE(a.proprio.joint_pos == b.proprio.joint_pos);
  EXPECT_TRUE(a.proprio.joint_vel == b.proprio.joint_vel);
  EXPECT_EQ(a.proprio.gripper_width, b.proprio.gripper_width);
  EXPECT_EQ(a.proprio.X_WT.translation, b.proprio.X_WT.translation);
  EXPECT_EQ(a.proprio.X_WT.rotation.coeffs(), b.proprio.X_WT.rotation.coeffs());
  ASSERT_EQ(a.images.size(), b.images.size());
  EXPECT_EQ(a.images[0].pixels, b.images[0].pixels);
  ASSERT_TRUE(b.state.has_value());
  EXPECT_EQ(a.state->human_joints_W, b.state->human_joints_W);
  ASSERT_EQ(b.state->objects.size(), 1u);
  EXPECT_EQ(b.state->objects[0].name, "cup");
  ASSERT_EQ(b.events.size(), 1u);
  EXPECT_EQ(b.events[0].name, "offer.go");
  EXPECT_EQ(b.events[0].detail, "go");
}

TEST(Preset, HribenchCarriesTheObservationExactlyThroughEveryLayout) {
  const policy::PolicySpec spec = rich_spec();
  PresetOptions options;
  options.served_spec = spec;
  options.allow_privileged = true;
  const script::Scenario scenario = script::load_scenario("tasks/I1_point_pick.yaml");
  policy::EpisodeInfo info;
  info.task = "point_pick";
  info.seed = 18446744073709551615ull;
  info.episode = std::make_shared<const script::EpisodeSpec>(script::sample(scenario, 3));
  const policy::Observation obs = rich_observation(spec);
  for (int layout = 0; layout < 3; ++layout) {
    auto preset = make_preset(options, "test");
    preset->begin(info);
    ObservationGroups groups;
    if (layout == 0) {
      groups = openpi_groups(unpack(pack(openpi_request(preset->encode(obs)), ArrayCodec::kOpenpi)).map("r"));
    } else {
      const Gr00tEra era = layout == 1 ? Gr00tEra::kN15 : Gr00tEra::kN16;
      groups = gr00t_groups(unpack(pack(gr00t_request(preset->encode(obs), era), ArrayCodec::kGr00t)).map("r"));
    }
    const NativeQuery query = decode_native(groups, spec);
    ASSERT_TRUE(query.start.has_value()) << layout;
    EXPECT_EQ(query.start->seed, info.seed);
    ASSERT_NE(query.start->episode, nullptr);
    EXPECT_EQ(script::spec_hash(*query.start->episode), script::spec_hash(*info.episode));
    expect_same(obs, query.observation);
    // The episode's start is sent once.
    EXPECT_FALSE(decode_native(openpi_groups(openpi_request(preset->encode(obs))), spec).start.has_value());
  }
}

TEST(Preset, APrivilegedServerNeedsPrivilegedInTheReference) {
  PresetOptions options;
  options.served_spec = rich_spec();
  const std::string message = ::hribench::testing::error_of([&] { make_preset(options, "policy openpi://h:1"); });
  EXPECT_NE(message.find("privileged=1"), std::string::npos) << message;
  options.name = "aloha";
  const std::string unknown = ::hribench::testing::error_of([&] { make_preset(options, "policy openpi://h:1"); });
  EXPECT_NE(unknown.find("a preset (droid, hribench, libero)"), std::string::npos) << unknown;
}

ActionGroups actions(std::vector<double> values, size_t width) {
  return {{"actions", NdArray::from_doubles(values, {values.size() / width, width}, "<f4")}};
}

TEST(Preset, LiberoStateImagesAndScaledActions) {
  PresetOptions options;
  options.name = "libero";
  auto preset = make_preset(options, "test");
  const policy::PolicySpec spec = preset->spec();
  EXPECT_EQ(spec.replan_every, 5);
  policy::Observation obs = rich_observation(spec);
  obs.images[0].pixels[0] = 1;  // top-left of agentview
  obs.proprio.gripper_width = 0.06;
  preset->begin(policy::EpisodeInfo{});
  const ObservationGroups g = preset->encode(obs);
  ASSERT_EQ(g.video.size(), 2u);
  EXPECT_EQ(g.video[0].first, "image");
  EXPECT_EQ(g.video[1].first, "wrist_image");
  const NdArray& image = g.video[0].second;
  EXPECT_EQ(static_cast<uint8_t>(image.data[(224 - 1) * 3]), 1);  // mirrored: now top-right
  ASSERT_EQ(g.state.size(), 1u);
  const std::vector<double> state = g.state[0].second.to_doubles("state");
  ASSERT_EQ(state.size(), 8u);
  EXPECT_FLOAT_EQ(static_cast<float>(state[0]), 0.3f);
  EXPECT_NEAR(state[5], M_PI / 2, 1e-6);  // a quarter turn about z
  EXPECT_NEAR(state[3], 0, 1e-7);
  EXPECT_FLOAT_EQ(static_cast<float>(state[6]), 0.03f);
  EXPECT_FLOAT_EQ(static_cast<float>(state[7]), -0.03f);
  const policy::ActionChunk chunk = preset->decode(actions({1, 0, -0.5, 0, 0.25, -2, -1, 0, 0, 0, 0, 0, 0, 1}, 7));
  ASSERT_EQ(chunk.actions.size(), 2u);
  EXPECT_NEAR(chunk.actions[0][0], 0.05, 1e-9);
  EXPECT_NEAR(chunk.actions[0][2], -0.025, 1e-9);
  EXPECT_NEAR(chunk.actions[0][4], 0.125, 1e-9);
  EXPECT_NEAR(chunk.actions[0][5], -0.5, 1e-9);  // clipped to -1, then 0.5 rad: the runner refuses it
  EXPECT_EQ(chunk.actions[0][6], 1.0);           // -1: open
  EXPECT_EQ(chunk.actions[1][6], 0.0);           // +1: closed
}

TEST(Preset, DroidIntegratesJointVelocitiesFromTheObservedJoints) {
  PresetOptions options;
  options.name = "droid";
  auto preset = make_preset(options, "test");
  const policy::PolicySpec spec = preset->spec();
  EXPECT_EQ(spec.action_space, policy::ActionSpace::kJointPos);
  EXPECT_EQ(spec.replan_every, 8);
  policy::EpisodeInfo info;
  info.control_dt = 0.05;
  preset->begin(info);
  policy::Observation obs = testing::observation(spec);
  obs.proprio.gripper_width = 0.02;  // of the Panda's 0.08
  const ObservationGroups g = preset->encode(obs);
  EXPECT_EQ(g.video[0].first, "exterior_image_1_left");
  EXPECT_EQ(g.video[1].first, "wrist_image_left");
  EXPECT_EQ(g.state[0].first, "joint_position");
  EXPECT_FLOAT_EQ(static_cast<float>(g.state[1].second.to_doubles("g")[0]), 0.75f);  // DROID: 1 closed
  // 0.2 rad per 1/15 s tick = 0.15 rad per 50 ms step at |v| = 1; larger v is scaled down.
  const policy::ActionChunk chunk = preset->decode(actions({1, 0, 0, 0, 0, 0, 0, 0.7,  //
                                                            2, 1, 0, 0, 0, 0, 0, 0.2},
                                                           8));
  ASSERT_EQ(chunk.actions.size(), 2u);
  const model::JointVector& q = obs.proprio.joint_pos;
  EXPECT_NEAR(chunk.actions[0][0], q[0] + 0.15, 1e-6);
  EXPECT_NEAR(chunk.actions[1][0], q[0] + 0.3, 1e-6);
  EXPECT_NEAR(chunk.actions[1][1], q[1] + 0.075, 1e-6);
  EXPECT_NEAR(chunk.actions[1][2], q[2], 1e-6);
  EXPECT_EQ(chunk.actions[0][7], 0.0);  // 0.7 > 0.5: closed
  EXPECT_EQ(chunk.actions[1][7], 1.0);
}

}  // namespace
}  // namespace hribench::remote
