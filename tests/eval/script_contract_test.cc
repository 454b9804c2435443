#include "eval/script_contract.h"

#include <gtest/gtest.h>

#include "core/errors.h"

namespace hribench::eval {
namespace {

// A hand-built graph shaped like the handover_h2r example of SCRIPTS.md.
script::ActGraph handover_graph() {
  script::ActGraph g;
  g.event_names = {"offer.start", "offer.end", "offer.hold_stable", "take.start", "take.end",
                   "stop.start", "go.start"};
  script::CompiledAct offer;
  offer.name = "offer";
  offer.human = true;
  offer.start_event = 0;
  offer.end_event = 1;
  offer.cue = script::CompiledCue{2, 4.0, "go"};
  offer.disruption = true;
  script::CompiledAct take;
  take.name = "take";
  take.human = false;
  take.constraints.after = 2;
  take.constraints.sync_with = 2;
  take.constraints.sync_offset = 1.0;
  take.constraints.sync_tolerance = 1.5;
  take.constraints.still_from = 5;
  take.constraints.still_to = 6;
  g.acts = {offer, take};
  return g;
}

TEST(ScriptContract, CuesActsAndConstraints) {
  const ScenarioContract c = contract_from_act_graph(handover_graph());
  ASSERT_EQ(c.cues.size(), 1u);
  EXPECT_EQ(c.cues[0].event, "offer.hold_stable");
  EXPECT_EQ(c.cues[0].kind, CueKind::kGo);
  EXPECT_DOUBLE_EQ(c.cues[0].window, 4.0);
  ASSERT_EQ(c.robot_acts.size(), 1u);
  EXPECT_EQ(c.robot_acts[0].name, "take");
  ASSERT_EQ(c.orders.size(), 2u);
  EXPECT_EQ(c.orders[0].kind, OrderKind::kAfter);
  EXPECT_EQ(c.orders[0].event, "offer.hold_stable");
  EXPECT_EQ(c.orders[1].kind, OrderKind::kStill);
  EXPECT_EQ(c.orders[1].from_event, "stop.start");
  EXPECT_EQ(c.orders[1].to_event, "go.start");
  ASSERT_EQ(c.syncs.size(), 1u);
  EXPECT_EQ(c.syncs[0].human_event, "offer.hold_stable");
  EXPECT_EQ(c.syncs[0].robot_event, "take.end");
  EXPECT_DOUBLE_EQ(c.syncs[0].offset, 1.0);
  EXPECT_DOUBLE_EQ(c.syncs[0].tolerance, 1.5);
  EXPECT_EQ(c.disruption_event, "offer.start");
  // A `within` window becomes a go cue on the act's `after` event.
  script::ActGraph g = handover_graph();
  g.acts[1].constraints.within = 2.5;
  const ScenarioContract w = contract_from_act_graph(g);
  ASSERT_EQ(w.cues.size(), 2u);
  EXPECT_EQ(w.cues[1].name, "take");
  EXPECT_EQ(w.cues[1].event, "offer.hold_stable");
  EXPECT_DOUBLE_EQ(w.cues[1].window, 2.5);
  EXPECT_FALSE(c.contradiction);
}

TEST(ScriptContract, UnknownCueKindIsAnInputError) {
  script::ActGraph g = handover_graph();
  g.acts[0].cue->kind = "wave";
  try {
    contract_from_act_graph(g);
    FAIL();
  } catch (const core::InputError& e) {
    EXPECT_STREQ(e.what(), "act offer: cue kind: expected go, stop or intrusion, got 'wave'");
  }
}

}  // namespace
}  // namespace hribench::eval
