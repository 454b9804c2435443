#include "script/predicate.h"

#include <gtest/gtest.h>

#include <optional>
#include <string>

#include "core/errors.h"

namespace hribench::script {
namespace {

const std::vector<std::string> kObjects = {"cup", "bin", "plate", "box"};

std::string error_of(const std::string& source) {
  try {
    bind_predicate(source, kObjects);
  } catch (const core::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

ObjectState box(core::Vec3 p, core::Vec3 half) {
  ObjectState o;
  o.X_WO.translation = p;
  o.half_extents = half;
  o.p_WO_initial = p;
  return o;
}

// A table scene: cup on the table, bin, plate and box nearby; hands far away.
WorldSnapshot scene() {
  WorldSnapshot w;
  w.objects = {box({0.5, 0.0, 0.80}, {0.03, 0.03, 0.05}), box({0.5, 0.3, 0.83}, {0.10, 0.10, 0.08}),
               box({0.5, -0.3, 0.76}, {0.10, 0.10, 0.01}), box({0.7, 0.0, 0.85}, {0.1, 0.1, 0.1})};
  w.X_WT.translation = {0.3, 0.0, 1.0};
  w.hands[kLeftHand].p_W = {1.5, 0.3, 0.9};
  w.hands[kRightHand].p_W = {1.5, -0.3, 0.9};
  return w;
}

bool eval_once(const std::string& source, const WorldSnapshot& w) {
  const BoundPredicate p = bind_predicate(source, kObjects);
  PredicateMemory m = make_memory(p);
  return evaluate(p, w, m);
}

TEST(PredicateTest, TypeChecksArityKindsAndNames) {
  EXPECT_EQ(error_of("grasp(robot, cup)"),
            ": expected a predicate (grasped, held, held_for, in, on, near, moved, dropped, at_home, "
            "still, clear, open, tilt, ever, not, and, or), got 'grasp'");
  EXPECT_EQ(error_of("near(robot, cup)"), ": expected 3 argument(s): near(A, B, METRES), got 2");
  EXPECT_EQ(error_of("grasped(robot, cup, 1)"), ": expected 2 argument(s): grasped(robot, OBJECT), got more");
  EXPECT_EQ(error_of("grasped(cup, robot)"), ": expected robot as argument 1 of grasped(robot, OBJECT), got 'cup'");
  EXPECT_EQ(error_of("in(mug, bin)"),
            ": expected a scene object as argument 1 of in(OBJECT, CONTAINER) (scene objects: cup, bin, plate, "
            "box), got 'mug'");
  EXPECT_EQ(error_of("held(human.middle, cup)"),
            ": expected human.left, human.right or human.any as argument 1 of held(human.left|right|any, "
            "OBJECT), got 'human.middle'");
  EXPECT_EQ(error_of("moved(cup, -1)"), ": expected a number >= 0 as argument 2 of moved(OBJECT, METRES), got '-1'");
  EXPECT_EQ(error_of("tilt(cup)"), ": expected tilt(OBJECT) < DEGREES or tilt(OBJECT) > DEGREES, got the end");
  EXPECT_EQ(error_of("dropped(cup) < 3"), ": expected a comparison only after tilt(...), got '<' after dropped");
  EXPECT_EQ(error_of("in(cup, bin) and"), ": expected a predicate, got the end");
  EXPECT_EQ(error_of(""), ": expected a predicate, got nothing");
  EXPECT_EQ(error_of("(in(cup, bin)"), ": expected ')', got the end");
  EXPECT_NE(error_of(std::string(40, '(') + "still(robot)" + std::string(40, ')')).find("nested at most 16"),
            std::string::npos);
  EXPECT_EQ(error_of("not in(cup, bin) and (held(human.any, cup) or tilt(plate) > 10)"), "(no error)");
  EXPECT_EQ(error_of("ever grasped(robot, cup)"), ": expected '(', got 'grasped'");
  EXPECT_EQ(error_of("ever(grasped(robot, cup)"), ": expected ')', got the end");
  EXPECT_EQ(error_of("ever(grasped(robot, mug))"),
            ": expected a scene object as argument 2 of grasped(robot, OBJECT) (scene objects: cup, bin, plate, "
            "box), got 'mug'");
  EXPECT_EQ(error_of("ever(grasped(robot, cup) and moved(cup, 0.1)) and not ever(dropped(cup))"), "(no error)");
}

TEST(PredicateTest, GeometryAtoms) {
  WorldSnapshot w = scene();
  EXPECT_TRUE(eval_once("on(cup, table)", w));
  EXPECT_FALSE(eval_once("in(cup, bin)", w));
  EXPECT_TRUE(eval_once("clear(plate)", w));
  EXPECT_FALSE(eval_once("near(robot, cup, 0.1)", w));
  EXPECT_TRUE(eval_once("near(robot, cup, 0.3)", w));
  // Into the bin: inside its box, resting on its bottom.
  w.objects[0].X_WO.translation = {0.52, 0.28, 0.80};
  EXPECT_TRUE(eval_once("in(cup, bin)", w));
  EXPECT_TRUE(eval_once("moved(cup, 0.2)", w));
  EXPECT_FALSE(eval_once("moved(cup, 0.5)", w));
  EXPECT_FALSE(eval_once("on(cup, bin)", w));  // inside, not on top
  // Not "in" while the robot grasps it.
  w.objects[0].left_finger_contact = w.objects[0].right_finger_contact = true;
  EXPECT_FALSE(eval_once("in(cup, bin)", w));
  EXPECT_TRUE(eval_once("grasped(robot, cup)", w));
  // On the plate: bottom 0.77 at the plate top 0.77, over its footprint.
  w = scene();
  w.objects[0].X_WO.translation = {0.5, -0.3, 0.82};
  EXPECT_TRUE(eval_once("on(cup, plate)", w));
  EXPECT_FALSE(eval_once("clear(plate)", w));
  w.objects[0].v_WO = {0.1, 0, 0};  // still sliding
  EXPECT_FALSE(eval_once("on(cup, plate)", w));
  // A palm over the plate.
  w = scene();
  w.hands[kRightHand].p_W = {0.55, -0.3, 0.9};
  EXPECT_FALSE(eval_once("clear(plate)", w));
  EXPECT_TRUE(eval_once("near(human.right, plate, 0.2)", w));
}

TEST(PredicateTest, LidTiltHomeAndHands) {
  WorldSnapshot w = scene();
  w.objects[3].lid_deg = 80;
  EXPECT_TRUE(eval_once("open(box, 60)", w));
  EXPECT_FALSE(eval_once("open(box, 90)", w));
  w.objects[2].X_WO.rotation = core::axis_angle(core::Vec3::UnitX(), core::deg_to_rad(20));
  EXPECT_TRUE(eval_once("tilt(plate) > 15", w));
  EXPECT_FALSE(eval_once("tilt(plate) < 15", w));
  w.home_distance = 0.02;
  EXPECT_TRUE(eval_once("at_home(robot)", w));
  w.home_distance = 0.05;
  EXPECT_FALSE(eval_once("at_home(robot)", w));
  w.hands[kLeftHand].held_object = 0;
  EXPECT_TRUE(eval_once("held(human.left, cup)", w));
  EXPECT_TRUE(eval_once("held(human.any, cup)", w));
  EXPECT_FALSE(eval_once("held(human.right, cup)", w));
  EXPECT_TRUE(eval_once("not held(human.right, cup) and (held(human.left, bin) or held(human.left, cup))", w));
}

// held_for, still and dropped remember the past: fed steps in time order.
TEST(PredicateTest, MemoryAcrossSteps) {
  const BoundPredicate held = bind_predicate("held_for(robot, cup, 0.2)", kObjects);
  const BoundPredicate still = bind_predicate("still(robot)", kObjects);
  const BoundPredicate dropped = bind_predicate("dropped(cup)", kObjects);
  PredicateMemory mh = make_memory(held), ms = make_memory(still), md = make_memory(dropped);
  double first_held = -1, first_still = -1;
  for (int k = 0; k <= 40; ++k) {
    WorldSnapshot w = scene();
    w.time = k * 0.05;
    const bool grasp = k >= 10 && k != 14;  // a one-step slip at k = 14 restarts the count
    w.objects[0].left_finger_contact = w.objects[0].right_finger_contact = grasp;
    w.v_WT = k < 20 ? core::Vec3(0.1, 0, 0) : core::Vec3::Zero();
    if (k == 30) w.objects[0].v_WO = {0, 0, -2.0};  // falls, free
    if (k == 30) w.objects[0].left_finger_contact = w.objects[0].right_finger_contact = false;
    if (evaluate(held, w, mh) && first_held < 0) first_held = w.time;
    if (evaluate(still, w, ms) && first_still < 0) first_still = w.time;
    EXPECT_EQ(evaluate(dropped, w, md), k >= 30) << k;
  }
  EXPECT_DOUBLE_EQ(first_held, 19 * 0.05);   // grasped again from k = 15, 0.2 s later
  EXPECT_DOUBLE_EQ(first_still, 24 * 0.05);  // still from k = 20, for 0.2 s
}

// ever(P) latches the first step P holds and keeps evaluating P, so a remembered condition
// inside it counts on after the latch.
TEST(PredicateTest, EverLatchesTheFirstStepItsChildHolds) {
  const BoundPredicate p = bind_predicate("ever(held_for(robot, cup, 0.1) and moved(cup, 0.05))", kObjects);
  const BoundPredicate later = bind_predicate("ever(held_for(robot, cup, 0.3))", kObjects);
  EXPECT_EQ(p.slots, 2u);  // the latch and held_for's start
  PredicateMemory m = make_memory(p), ml = make_memory(later);
  for (int k = 0; k <= 20; ++k) {
    WorldSnapshot w = scene();
    w.time = k * 0.05;
    // Grasped from k = 2 to 9 (lifted 0.1 m from k = 5), free again from k = 10.
    const bool grasp = k >= 2 && k <= 9;
    w.objects[0].left_finger_contact = w.objects[0].right_finger_contact = grasp;
    if (k >= 5 && k <= 9) w.objects[0].X_WO.translation.z() += 0.1;
    EXPECT_EQ(evaluate(p, w, m), k >= 5) << k;      // held 0.15 s and lifted at k = 5
    EXPECT_EQ(evaluate(later, w, ml), k >= 8) << k;  // held for 0.3 s at k = 8
  }
  EXPECT_FALSE(eval_once("ever(grasped(robot, cup))", scene()));
  EXPECT_TRUE(eval_once("not ever(grasped(robot, cup))", scene()));
}

// and/or evaluate every child, so a remembered condition keeps counting inside them.
TEST(PredicateTest, CompoundsKeepChildMemoriesCurrent) {
  const BoundPredicate p = bind_predicate("at_home(robot) or held_for(robot, cup, 0.1)", kObjects);
  PredicateMemory m = make_memory(p);
  WorldSnapshot w = scene();
  w.objects[0].left_finger_contact = w.objects[0].right_finger_contact = true;
  w.home_distance = 0;
  w.time = 0;
  EXPECT_TRUE(evaluate(p, w, m));  // at home; held_for starts counting anyway
  w.home_distance = 1;
  w.time = 0.1;
  EXPECT_TRUE(evaluate(p, w, m));
}

// What a logged predicate says about holding, asked typed: grasped(robot, o), held(human.H, o)
// and held_for(A, o, s) alone; nothing for other atoms or for a holding atom within not/and/or.
TEST(PredicateTest, HoldingAtomsAreReadTyped) {
  const auto holding = [](const std::string& source) { return holding_atom(bind_predicate(source, kObjects).root); };
  const std::optional<HoldingAtom> grasp = holding("grasped(robot, bin)");
  ASSERT_TRUE(grasp);
  EXPECT_EQ(grasp->atom, Atom::kGrasped);
  EXPECT_EQ(grasp->holder.kind, Arg::Kind::kRobot);
  EXPECT_EQ(grasp->object, 1);
  EXPECT_TRUE(grasp->robot_grasps(1));
  EXPECT_FALSE(grasp->robot_grasps(0));
  EXPECT_FALSE(grasp->human_holds(1));

  const std::optional<HoldingAtom> left = holding("held(human.left, plate)");
  ASSERT_TRUE(left);
  EXPECT_EQ(left->holder.kind, Arg::Kind::kHand);
  EXPECT_EQ(left->holder.index, kLeftHand);
  EXPECT_TRUE(left->human_holds(2));
  EXPECT_FALSE(left->robot_grasps(2));
  const std::optional<HoldingAtom> any = holding("held(human.any, cup)");
  ASSERT_TRUE(any);
  EXPECT_EQ(any->holder.kind, Arg::Kind::kAnyHand);
  EXPECT_TRUE(any->human_holds(0));
  // Written without spaces, it is the same atom.
  const std::optional<HoldingAtom> tight = holding("held(human.right,box)");
  ASSERT_TRUE(tight);
  EXPECT_EQ(tight->holder.index, kRightHand);
  EXPECT_TRUE(tight->human_holds(3));

  const std::optional<HoldingAtom> held_for = holding("held_for(robot, cup, 0.5)");
  ASSERT_TRUE(held_for);
  EXPECT_EQ(held_for->atom, Atom::kHeldFor);
  EXPECT_FALSE(held_for->robot_grasps(0));  // grasped(robot, cup) asks for the atom itself
  EXPECT_FALSE(held_for->human_holds(0));

  EXPECT_FALSE(holding("in(cup, bin)"));
  EXPECT_FALSE(holding("held(human.any, cup) and not grasped(robot, cup)"));
  EXPECT_FALSE(holding("not grasped(robot, cup)"));
  EXPECT_FALSE(holding("(grasped(robot, cup)) or at_home(robot)"));
}

// Text that is not a predicate of the episode fails to bind before anything is asked of it.
TEST(PredicateTest, HoldingAtomsOfBadTextFailWithTheArgumentExpected) {
  EXPECT_EQ(error_of("held(robot, cup)"),
            ": expected human.left|right|any as argument 1 of held(human.left|right|any, OBJECT), got 'robot'");
  EXPECT_EQ(error_of("grasped(robot, mug)"),
            ": expected a scene object as argument 2 of grasped(robot, OBJECT) (scene objects: cup, bin, plate, box), "
            "got 'mug'");
}

}  // namespace
}  // namespace hribench::script
