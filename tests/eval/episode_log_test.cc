#include "eval/episode_log.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "core/errors.h"
#include "core/rng.h"
#include "eval/episode_builder.h"
#include "eval/metrics.h"

namespace hribench::eval {
namespace {

using testing::EpisodeBuilder;

EpisodeLog rich_log() {
  EpisodeBuilder b(3.0, {"success", "dropped"});
  b.move_x(0.5, 2.0, 0.1237).grip(1.0, 1.5, -0.03).predicate("success", 2.2, 3.0);
  b.event(0.4, "offer.start", EventKind::kActStart).event(1.0, "offer.hold_stable");
  b.event(2.0, "take.end", EventKind::kActEnd, Actor::kRobot);
  b.separation(1.0, 2.0, 0.3141592653589793, 0.1, 0.2);
  b.contact(1.5, 1.6, testing::human_contact("right_hand", human::BodyRegion::kHand, 3.25));
  b.contact(1.5, 1.5, Contact{"panda_link4", false, ContactOther::kEnvironment, "table", {}, 1e-7});
  EpisodeLog log = b.log();
  log.steps[3].human_joints_W[5] = core::Vec3(0.1, 1.0 / 3.0, -2e-300);
  log.steps[4].object_poses[1].rotation = core::Quat(0.5, 0.5, -0.5, 0.5);
  // What the robot was told, velocities, the lid and the skeleton's rotations.
  log.action_space = policy::ActionSpace::kJointPos;
  log.steps[5].action = {0.1, -0.2, 0.3, -2.0, 0.0, 1.5, 0.7, 1.0};
  log.steps[5].joint_target = {0.1, -0.2, 0.3, -2.0, 0.0, 1.5, 0.7};
  log.steps[5].gripper_target = 0.08;
  log.steps[5].joint_vel = {1e-3, 0, 0, 0, 0, 0, -2.5};
  log.steps[5].finger_pos = {0.04, 0.0399999};
  log.steps[6].lid_angles[1] = 1.0 / 7.0;
  log.steps[6].human_pose.X_WP.translation = core::Vec3(1.2, 0.1, 0.9);
  log.steps[6].human_pose.local[3] = core::Quat(0.8, 0.6, 0, 0);
  log.steps[6].human_pose.hands[1] = {0.25, 1.0 / 3.0};
  log.events.back().detail = "grasped(robot, cube)";
  log.status = core::EpisodeStatus::kPolicyError;
  log.status_reason = "non_finite: action 0 value 1: nan";
  return log;
}

// A path unique to this process and test (parallel ctest runs never share one).
std::filesystem::path temp_file(const std::string& name) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  return std::filesystem::path(::testing::TempDir()) /
         ("hribench_eval_" + std::string(test->test_suite_name()) + "_" + test->name() + "_" +
          std::to_string(getpid()) + "_" + name);
}

TEST(EpisodeLog, RoundTripIsExact) {
  const EpisodeLog log = rich_log();
  const std::string bytes = encode_episode_log(log);
  const EpisodeLog back = decode_episode_log(bytes, "mem");
  EXPECT_TRUE(identical(back, log));
  EXPECT_EQ(encode_episode_log(back), bytes);
  const auto path = temp_file("roundtrip.hlog");
  save_episode_log(log, path);
  EXPECT_TRUE(identical(load_episode_log(path), log));
  std::filesystem::remove(path);
}

TEST(EpisodeLog, IdenticalComparesEveryField) {
  const EpisodeLog log = rich_log();
  EXPECT_TRUE(identical(log, log));
  EpisodeLog other = log;
  other.steps[7].human_joints_W[21].z() += 1e-15;
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.steps[30].contacts[0].normal_force = 3.2500000000000004;
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.steps[2].object_poses[1].rotation.w() = -0.0;
  other.steps[2].object_poses[1].rotation.x() = 0.0;
  EXPECT_FALSE(identical(log, other));  // w flipped from 1 to -0
  other = log;
  other.steps[6].human_pose.local[3].y() = 1e-300;
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.steps[6].human_pose.hands[1].point = std::nextafter(1.0 / 3.0, 1.0);
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.steps[6].human_pose.hands[0].grip = 1e-300;
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.steps[6].lid_angles[1] = 0;
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.steps[5].action[7] = 0.5;
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.steps[5].joint_vel[6] = -2.4;
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.action_space = policy::ActionSpace::kEeDelta;
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.events[1].detail = "x";
  EXPECT_FALSE(identical(log, other));
  other = log;
  other.status_reason.clear();
  EXPECT_FALSE(identical(log, other));
}

TEST(EpisodeLog, ReloadedLogRescoresIdentically) {
  ScenarioContract contract;
  contract.robot_acts.push_back({"take", core::Vec3(1.0, 0, 1.0)});
  contract.syncs.push_back({"grasp", "offer.hold_stable", "take.end", 1.0, 1.5});
  contract.cues.push_back({"offer", "offer.hold_stable", CueKind::kGo, 2.0, core::Vec3(1.0, 0, 1.0)});
  EpisodeLog log = rich_log();
  log.status = core::EpisodeStatus::kOk;
  const EpisodeMetrics live = compute_metrics(contract, log);
  const EpisodeMetrics again = compute_metrics(contract, decode_episode_log(encode_episode_log(log), "m"));
  EXPECT_EQ(live.completion_time, again.completion_time);
  EXPECT_EQ(live.response_latency, again.response_latency);
  EXPECT_EQ(live.tsync, again.tsync);
  EXPECT_EQ(live.hcs, again.hcs);
  EXPECT_EQ(live.monitored_time, again.monitored_time);
  EXPECT_EQ(live.r_idle, again.r_idle);
  EXPECT_EQ(live.labels, again.labels);
  EXPECT_EQ(live.success, again.success);
}

TEST(EpisodeLog, TruncatedFileIsAClearError) {
  const std::string bytes = encode_episode_log(rich_log());
  for (const size_t keep : {size_t{0}, size_t{5}, size_t{12}, size_t{30}, bytes.size() - 1}) {
    try {
      decode_episode_log(std::string_view(bytes).substr(0, keep), "run/ep.hlog");
      FAIL() << keep;
    } catch (const core::InputError& e) {
      EXPECT_EQ(e.where(), "run/ep.hlog");
      if (keep >= 20) {
        EXPECT_NE(std::string(e.what()).find("truncated episode log"), std::string::npos) << e.what();
      }
    }
  }
}

TEST(EpisodeLog, CorruptFileIsAClearError) {
  std::string bytes = encode_episode_log(rich_log());
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x10);
  try {
    decode_episode_log(bytes, "ep.hlog");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "ep.hlog: corrupt episode log (checksum mismatch)");
  }
  try {
    decode_episode_log("PNG\x89 not a log at all....", "x.png");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "x.png: expected an HRIBench episode log (starting with HRIBLOG), got a file "
                 "of another kind");
  }
  std::string future = encode_episode_log(rich_log());
  future[8] = 9;  // format version 9
  try {
    decode_episode_log(future, "f.hlog");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "f.hlog: expected episode log format version 3, got format version 9");
  }
  // A version-2 file (before hand shapes were logged).
  std::string old = encode_episode_log(rich_log());
  old[8] = 2;
  try {
    decode_episode_log(old, "v2.hlog");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "v2.hlog: expected episode log format version 3, got format version 2");
  }
  std::string trailing = encode_episode_log(rich_log()) + "x";
  EXPECT_THROW(decode_episode_log(trailing, "t"), core::InputError);
}

// Re-encodes a payload with a valid header and checksum, so only the payload's counts are
// tested.
std::string with_payload(const std::string& payload) {
  std::string bytes("HRIBLOG\0", 8);
  const uint32_t version = kEpisodeLogVersion;
  bytes.append(reinterpret_cast<const char*>(&version), sizeof(version));
  const uint64_t size = payload.size();
  bytes.append(reinterpret_cast<const char*>(&size), sizeof(size));
  bytes += payload;
  const uint64_t sum = core::fnv1a64(payload);
  bytes.append(reinterpret_cast<const char*>(&sum), sizeof(sum));
  return bytes;
}

TEST(EpisodeLog, DeclaredCountsAreCheckedAgainstTheBytesLeft) {
  // A log of no steps, then its step count raised: each step needs far more than 8 bytes
  // (the human pose alone is 22 x 7 doubles), so a count the remaining bytes cannot hold is
  // corrupt before anything is allocated.
  EpisodeLog log = rich_log();
  log.steps.clear();
  log.events.clear();
  const std::string bytes = encode_episode_log(log);
  std::string payload = bytes.substr(20, bytes.size() - 28);
  // The step count sits before the event count (the last 8 bytes).
  const size_t at = payload.size() - 16;
  uint64_t steps = 0;
  std::memcpy(&steps, payload.data() + at, sizeof(steps));
  ASSERT_EQ(steps, 0u);
  payload += std::string(2000, '\0');  // room for 250 counts of 8 bytes, not for 2 steps
  steps = 2;
  std::memcpy(payload.data() + at, &steps, sizeof(steps));
  try {
    decode_episode_log(with_payload(payload), "big.hlog");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind("big.hlog: corrupt episode log (bad step count at byte", 0), 0u)
        << e.what();
  }
}

TEST(EpisodeLog, SaveReplacesAtomically) {
  const auto path = temp_file("atomic.hlog");
  save_episode_log(rich_log(), path);
  EpisodeLog other = rich_log();
  other.seed = 99;
  save_episode_log(other, path);
  EXPECT_EQ(load_episode_log(path).seed, 99u);
  std::filesystem::path temp = path;
  temp += ".tmp";
  EXPECT_FALSE(std::filesystem::exists(temp));
  std::filesystem::remove(path);
  try {
    save_episode_log(other, "/nonexistent/dir/ep.hlog");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/dir/ep.hlog: cannot write the file: No such file or directory");
  }
}

TEST(EpisodeLog, MissingFileIsAClearError) {
  try {
    load_episode_log("/nonexistent/ep.hlog");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/ep.hlog: cannot open the episode log");
  }
}

TEST(EpisodeLog, ConsistencyCheck) {
  EpisodeLog log = rich_log();
  EXPECT_NO_THROW(check_episode_log(log, "log"));
  log.steps[2].time = log.steps[1].time;
  try {
    check_episode_log(log, "log");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "log: step 2: expected a finite time after the previous step's, got 0.05");
  }
  log = rich_log();
  log.steps[1].predicates.pop_back();
  EXPECT_THROW(check_episode_log(log, "log"), core::InputError);
  log = rich_log();
  log.steps[30].contacts[0].region.reset();
  try {
    check_episode_log(log, "log");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(),
                 "log: step 30 contact left_finger_pad|right_hand: expected a body region "
                 "exactly for human contacts, got no region");
  }
}

TEST(EpisodeLog, EventLookup) {
  const EpisodeLog log = rich_log();
  EXPECT_DOUBLE_EQ(*log.event_time("offer.hold_stable"), 1.0);
  EXPECT_FALSE(log.event_time("release.end").has_value());
  EXPECT_EQ(*log.predicate_index("dropped"), 1u);
  EXPECT_NEAR(log.duration(), 3.0, 1e-12);
  EXPECT_EQ(to_string(EventKind::kPredicateChange), "predicate_change");
  EXPECT_EQ(to_string(ContactOther::kEnvironment), "environment");
}

}  // namespace
}  // namespace hribench::eval
