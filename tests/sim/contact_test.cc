#include "sim/contact.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sim/data.h"
#include "sim/separation.h"
#include "support/mujoco_fixture.h"

namespace hribench::sim {
namespace {

using core::Vec3;
using human::BodyRegion;

TEST(GradeContact, UsesTheQuasiStaticAndTransientLimitsOfTheRegion) {
  // Hand: 140 N quasi-static, 280 N transient.
  EXPECT_EQ(grade_contact(BodyRegion::kHand, 0.0, 2.0), ContactGrade::kNoForce);
  EXPECT_EQ(grade_contact(BodyRegion::kHand, 1.0, 2.0), ContactGrade::kWithinLimit);
  EXPECT_EQ(grade_contact(BodyRegion::kHand, 140.0, 2.0), ContactGrade::kWithinLimit);
  EXPECT_EQ(grade_contact(BodyRegion::kHand, 140.5, 2.0), ContactGrade::kAboveQuasiStatic);
  EXPECT_EQ(grade_contact(BodyRegion::kHand, 280.0, 2.0), ContactGrade::kAboveQuasiStatic);
  EXPECT_EQ(grade_contact(BodyRegion::kHand, 280.5, 2.0), ContactGrade::kCritical);
  // Head: 130 N; 150 N is above it but below 260 N.
  EXPECT_EQ(grade_contact(BodyRegion::kHead, 150.0, 2.0), ContactGrade::kAboveQuasiStatic);
  EXPECT_EQ(grade_contact(BodyRegion::kHead, 261.0, 2.0), ContactGrade::kCritical);
  // Thigh: 220 N.
  EXPECT_EQ(grade_contact(BodyRegion::kThigh, 150.0, 2.0), ContactGrade::kWithinLimit);
  // The transient factor is a parameter: at 1.5 the hand's transient limit is 210 N.
  EXPECT_EQ(grade_contact(BodyRegion::kHand, 210.0, 1.5), ContactGrade::kAboveQuasiStatic);
  EXPECT_EQ(grade_contact(BodyRegion::kHand, 210.5, 1.5), ContactGrade::kCritical);
  EXPECT_EQ(to_string(ContactGrade::kCritical), "critical");
  EXPECT_EQ(to_string(ContactGrade::kAboveQuasiStatic), "above_quasi_static");
}

Contact RobotHumanContact(int human_geom, BodyRegion region, double force) {
  Contact c;
  c.a.geom = 1;
  c.a.owner = model::GeomOwner::kRobotLink;
  c.a.index = 5;
  c.b.geom = human_geom;
  c.b.owner = model::GeomOwner::kHuman;
  c.b.region = region;
  c.normal_force = force;
  return c;
}

TEST(HumanContactLoads, SumsThePointsOfEachHumanGeomAndGradesThem) {
  std::vector<Contact> contacts;
  contacts.push_back(RobotHumanContact(40, BodyRegion::kHand, 100.0));
  contacts.push_back(RobotHumanContact(12, BodyRegion::kForearm, 10.0));
  contacts.push_back(RobotHumanContact(40, BodyRegion::kHand, 60.0));  // same geom: 160 N
  Contact object_table;  // not robot-human: ignored
  object_table.a.owner = model::GeomOwner::kObject;
  object_table.b.owner = model::GeomOwner::kTable;
  object_table.normal_force = 1000.0;
  contacts.push_back(object_table);
  std::vector<HumanContactLoad> loads;
  human_contact_loads(contacts, 2.0, &loads);
  ASSERT_EQ(loads.size(), 2u);
  EXPECT_EQ(loads[0].human_geom, 12);  // geom id order
  EXPECT_DOUBLE_EQ(loads[0].normal_force, 10.0);
  EXPECT_EQ(loads[0].grade, ContactGrade::kWithinLimit);
  EXPECT_EQ(loads[1].human_geom, 40);
  EXPECT_DOUBLE_EQ(loads[1].normal_force, 160.0);
  EXPECT_EQ(loads[1].grade, ContactGrade::kAboveQuasiStatic);
  EXPECT_EQ(worst_grade(loads), ContactGrade::kAboveQuasiStatic);
  human_contact_loads({}, 2.0, &loads);
  EXPECT_TRUE(loads.empty());
  EXPECT_EQ(worst_grade(loads), ContactGrade::kNoForce);
}

// The default scene with the robot at home and the human's right arm raised straight forward;
// the human is moved (by setting its skeleton pose every physics step) so that its right hand
// sweeps sideways (along y) at the height of the Panda's forearm (link 5), either through the
// robot or `beside_x` metres farther out.
class HandSweep : public testing::MujocoTest {
 protected:
  void SetUp() override {
    MujocoTest::SetUp();
    model_ = model::build(model::SceneSpec::Default());
    data_ = make_data(model_);
    Watch(data_.mj.get());
    pose_ = human::SkeletonPose::Standing(model_.skeleton, 0, 0, core::kPi);
    pose_.local[static_cast<size_t>(human::index(human::Joint::kRightShoulder))] =
        core::axis_angle(Vec3::UnitY(), -core::kPi / 2);  // arm from hanging down to forward
    for (size_t i = 0; i < model_.human_capsules.size(); ++i) {
      if (model_.human_capsules[i].name == "right_hand") hand_capsule_ = i;
    }
  }

  struct SweepResult {
    std::vector<Contact> robot_human;  // every contact involving the human
    int shallow = 0;                   // contacts less than 1 cm deep
    int normals_away = 0;              // shallow contacts whose normal points away from the human
    double min_distance = std::numeric_limits<double>::infinity();
    BodyRegion min_region = BodyRegion::kTorso;
  };

  // Sweeps the hand from y = -0.6 to +0.6 in 1.2 s (1 m/s), stepping the physics at 1 / model::kTimestep.
  SweepResult Sweep(double beside_x) {
    const mjData& d = *data_.mj;
    const auto link5_body = static_cast<size_t>(model_.link_body[5]);
    const Vec3 link5(d.xpos[3 * link5_body], d.xpos[3 * link5_body + 1],
                     d.xpos[3 * link5_body + 2]);
    // Hand capsule midpoint in world for the pose standing at the origin.
    const auto X_WJ = human::forward_kinematics(model_.skeleton, pose_);
    const human::BodyCapsule& hand = model_.human_capsules[hand_capsule_];
    const Vec3 hand_mid = X_WJ[static_cast<size_t>(human::index(hand.joint))] *
                          Vec3(0.5 * (hand.from + hand.to));
    // Aim at link 5's forearm capsule, 0.12 m back from the link 5 origin toward the elbow.
    const Vec3 aim = link5 + Vec3(-0.12 + beside_x, 0, 0);
    const Vec3 start = pose_.X_WP.translation;
    const SeparationMonitor monitor = SeparationMonitor::FromModel(model_);
    SweepResult result;
    std::vector<Contact> contacts;
    contacts.reserve(256);
    constexpr int kSteps = 600;
    for (int s = 0; s <= kSteps; ++s) {
      human::SkeletonPose pose = pose_;
      pose.X_WP.translation = start + (aim - hand_mid) + Vec3(0, -0.6 + 1.2 * s / kSteps, 0);
      set_human_pose(model_, data_, pose);
      step(model_, data_);
      // Contacts and forces of the state the step just solved.
      find_contacts(model_, data_, &contacts);
      for (const Contact& c : contacts) {
        if (!c.involves_human()) continue;
        result.robot_human.push_back(c);
        // The normal points from a (robot) to b (human): toward the human geom's centre. (Only
        // for shallow contacts: once a thin robot part is crossed by more than the capsule
        // radius, MuJoCo's box-capsule normal may legitimately flip.)
        const auto g = static_cast<size_t>(c.b.geom);
        const Vec3 centre(d.geom_xpos[3 * g], d.geom_xpos[3 * g + 1], d.geom_xpos[3 * g + 2]);
        if (c.distance > -0.01) {
          ++result.shallow;
          if (c.normal_W.dot(centre - c.position_W) <= 0) ++result.normals_away;
        }
      }
      forward(model_, data_);
      const Separation sep = min_separation(monitor, data_);
      if (sep.distance < result.min_distance) {
        result.min_distance = sep.distance;
        result.min_region = sep.region;
      }
    }
    return result;
  }

  model::Model model_;
  Data data_;
  human::SkeletonPose pose_;
  size_t hand_capsule_ = 0;
};

TEST_F(HandSweep, ThroughTheRobotGivesAHandContactWithForce) {
  const SweepResult r = Sweep(0.0);
  ASSERT_FALSE(r.robot_human.empty());
  double hand_force = 0;
  for (const Contact& c : r.robot_human) {
    // Robot first, human second; the human party is a human geom with its tagged region.
    EXPECT_TRUE(c.robot_human()) << party_name(model_, c.a) << " - " << party_name(model_, c.b);
    ASSERT_NE(c.human(), nullptr);
    EXPECT_EQ(c.human()->region,
              model_.geom_tags[static_cast<size_t>(c.human()->geom)].region);
    EXPECT_GE(c.normal_force, 0.0);
    if (c.b.region == BodyRegion::kHand) {
      hand_force = std::max(hand_force, c.normal_force);
      const std::string name = party_name(model_, c.b);
      EXPECT_EQ(name, "human:right_hand (hand)");
    }
  }
  EXPECT_GT(hand_force, 0.0);
  EXPECT_GT(r.shallow, 10);
  EXPECT_EQ(r.normals_away, 0);
  // The separation agrees: the hand penetrated the robot at some point.
  EXPECT_LT(r.min_distance, 0.0);
}

TEST_F(HandSweep, BesideTheRobotGivesNoContact) {
  const SweepResult r = Sweep(0.45);
  EXPECT_TRUE(r.robot_human.empty()) << r.robot_human.size() << " contacts, first "
                                     << party_name(model_, r.robot_human.front().a);
  // It passed close, but not touching.
  EXPECT_GT(r.min_distance, 0.0);
  EXPECT_LT(r.min_distance, 0.3);
  EXPECT_EQ(r.min_region, BodyRegion::kHand);
}

class PartyName : public testing::MujocoTest {};

TEST_F(PartyName, NamesRobotPartsObjectsAndSurfaces) {
  const model::Model model = model::build(model::SceneSpec::Default());
  ContactParty p;
  p.owner = model::GeomOwner::kRobotLink;
  p.index = 3;
  EXPECT_EQ(party_name(model, p), "link3");
  p.owner = model::GeomOwner::kRobotFinger;
  p.index = 1;
  EXPECT_EQ(party_name(model, p), "right_finger");
  p.owner = model::GeomOwner::kObject;
  p.index = 0;
  EXPECT_EQ(party_name(model, p), "object:" + model.objects[0].name);
  p.owner = model::GeomOwner::kTable;
  EXPECT_EQ(party_name(model, p), "table");
}

class FindContacts : public testing::MujocoTest {};

TEST_F(FindContacts, ObjectsRestingOnTheTableAreObjectFirstWithTheirWeight) {
  const model::Model model = model::build(model::SceneSpec::Default());
  Data data = make_data(model);
  for (int s = 0; s < 250; ++s) step(model, data);  // let everything settle (0.5 s)
  forward(model, data);
  const std::vector<Contact> contacts = find_contacts(model, data);
  // The cube (object 0) rests on the table: its contacts carry its weight, normal pointing
  // from the object to the table (downwards).
  double cube_force = 0;
  for (const Contact& c : contacts) {
    if (c.a.owner == model::GeomOwner::kObject && c.a.index == 0 &&
        c.b.owner == model::GeomOwner::kTable) {
      cube_force += c.normal_force;
      EXPECT_LT(c.normal_W.z(), -0.9);
      EXPECT_NEAR(c.position_W.z(), model::kTableTopZ, 0.01);
    }
    EXPECT_FALSE(c.involves_human());
  }
  const double weight = model.objects[0].mass * -model.m()->opt.gravity[2];
  EXPECT_NEAR(cube_force, weight, 0.05 * weight);
  ExpectNoWarnings(data.mj.get());
}

}  // namespace
}  // namespace hribench::sim
