// Robot descriptions (model/robot.h): joint vectors, the registry, the MJCF and ids derived from
// a description, and the rule that no source outside the description names the Panda's joint
// count or limits.

#include "model/robot.h"

#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/errors.h"
#include "model/model.h"
#include "support/mujoco_fixture.h"

namespace hribench::model {
namespace {

TEST(JointVector, SizedFixedCapacityValues) {
  JointVector v(3, 0.5);
  EXPECT_EQ(v.size(), 3u);
  EXPECT_EQ(v[2], 0.5);
  v[1] = -1;
  EXPECT_EQ(JointVector({0.5, -1, 0.5}), v);
  EXPECT_FALSE(JointVector({0.5, -1}) == v);  // sizes differ
  EXPECT_TRUE(JointVector().empty());
  double sum = 0;
  for (const double x : v) sum += x;
  EXPECT_EQ(sum, 0.0);
}

TEST(RobotRegistry, FindsThePandaAndNamesTheKnownRobots) {
  EXPECT_EQ(&robot_by_name("panda"), &panda());
  EXPECT_EQ(robot_by_name(kDefaultRobot).name, "panda");
  try {
    robot_by_name("so100");
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "robot: expected one of panda, got 'so100'");
  }
}

TEST(RobotDescription, PandaIsConsistent) {
  const Robot& r = panda();
  EXPECT_EQ(r.dof(), 7u);
  EXPECT_EQ(r.links.size(), r.dof() + 1);
  EXPECT_LE(r.dof(), kMaxArmDof);
  for (const ArmJoint& j : r.joints) {
    EXPECT_LT(j.q_min, j.q_max) << j.name;
    EXPECT_GE(j.home, j.q_min) << j.name;
    EXPECT_LE(j.home, j.q_max) << j.name;
    EXPECT_GT(j.tau_max, 0) << j.name;
    EXPECT_DOUBLE_EQ(j.kv, j.kp / 10) << j.name;
  }
  EXPECT_EQ(r.q_min().size(), r.dof());
  EXPECT_EQ(r.home()[3], r.joints[3].home);
  EXPECT_DOUBLE_EQ(r.gripper.max_width(), 0.08);
}

class RobotModelTest : public testing::MujocoTest {};

TEST_F(RobotModelTest, ModelCarriesItsRobotAndIdsPerJoint) {
  SceneSpec spec;
  spec.human.present = false;
  const Model model = build(spec);
  EXPECT_EQ(model.robot.name, "panda");
  ASSERT_EQ(model.arm_joint.size(), model.robot.dof());
  ASSERT_EQ(model.link_body.size(), model.robot.links.size());
  const mjModel* m = model.m();
  for (size_t i = 0; i < model.robot.dof(); ++i) {
    const ArmJoint& j = model.robot.joints[i];
    EXPECT_EQ(mj_id2name(m, mjOBJ_JOINT, model.arm_joint[i]), j.name);
    EXPECT_EQ(mj_id2name(m, mjOBJ_ACTUATOR, model.arm_actuator[i]), j.actuator);
    EXPECT_DOUBLE_EQ(m->actuator_gainprm[mjNGAIN * model.arm_actuator[i]], j.kp);
    EXPECT_DOUBLE_EQ(m->actuator_biasprm[mjNBIAS * model.arm_actuator[i] + 2], -j.kv);
    // The home keyframe holds the description's home pose, the servos aim at it.
    EXPECT_DOUBLE_EQ(m->key_qpos[model.arm_qpos_adr[i]], j.home);
    EXPECT_DOUBLE_EQ(m->key_ctrl[model.arm_actuator[i]], j.home);
  }
  EXPECT_DOUBLE_EQ(m->actuator_ctrlrange[2 * model.gripper_actuator + 1], model.robot.gripper.max_width());
  // Geoms of each link are tagged with its index.
  for (size_t k = 0; k < model.link_body.size(); ++k) {
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->geom_bodyid[g] != model.link_body[k]) continue;
      EXPECT_EQ(model.geom_tags[static_cast<size_t>(g)].owner, GeomOwner::kRobotLink);
      EXPECT_EQ(model.geom_tags[static_cast<size_t>(g)].index, static_cast<int>(k));
    }
  }
}

TEST(RobotModel, UnknownRobotInTheSceneIsAnInputError) {
  SceneSpec spec = SceneSpec::Default();
  spec.robot = "ur5";
  try {
    build(spec);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "robot: expected one of panda, got 'ur5'");
  }
}

// The Panda's numbers and a hard-coded 7-joint arm may appear only in its description.
TEST(RobotSources, NoPandaConstantsOutsideItsDescription) {
  const std::filesystem::path src = std::filesystem::path(HRIBENCH_SOURCE_DIR) / "src";
  const std::filesystem::path description = src / "model" / "panda.cc";
  // Joint position limits, velocity limits, home pose, TCP offset (docs/robots.md); the old
  // re-typed constants; fixed 7-element joint arrays and a 6 x 7 Jacobian.
  const std::regex panda(
      R"(2\.8973|1\.7628|3\.0718|0\.0698|3\.7525|0\.0175|\b2\.175\b|\b2\.61\b|1\.57079|0\.7853\b|0\.1034|)"
      R"(\bkArmDof\b|\bkArmJoints\b|\bkGripperMaxWidth\b|\bkMaxGripperWidth\b|\bkArmQM(in|ax)\b|\bkArmHome\b|)"
      R"(array<double,\s*7>|Matrix<double,\s*6,\s*7>|Matrix6x7|Vector7\b|panda_joint)");
  // The pattern catches what it is meant to.
  for (const char* bad : {"std::array<double, 7> q;", "q < 2.8973", "model::kArmDof", "x / kMaxGripperWidth"})
    EXPECT_TRUE(std::regex_search(std::string(bad), panda)) << bad;
  EXPECT_FALSE(std::regex_search(std::string("for (size_t i = 0; i < robot.dof(); ++i)"), panda));
  std::vector<std::string> offending;
  size_t files = 0;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(src)) {
    if (!entry.is_regular_file() || entry.path() == description) continue;
    const std::string ext = entry.path().extension().string();
    if (ext != ".cc" && ext != ".h") continue;
    ++files;
    std::ifstream in(entry.path());
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (!std::regex_search(text, panda)) continue;  // then name the lines
    std::istringstream lines(text);
    std::string line;
    for (int n = 1; std::getline(lines, line); ++n) {
      if (std::regex_search(line, panda))
        offending.push_back(std::filesystem::relative(entry.path(), src.parent_path()).string() + ":" +
                            std::to_string(n) + ": " + line);
    }
  }
  EXPECT_GT(files, 50u) << "the source tree was not found at " << src;
  std::string list;
  for (const std::string& o : offending) list += o + "\n";
  EXPECT_TRUE(offending.empty()) << "Panda constants outside src/model/panda.cc:\n" << list;
}

}  // namespace
}  // namespace hribench::model
