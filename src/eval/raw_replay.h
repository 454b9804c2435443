#pragma once
// Raw MuJoCo making an episode's physics steps: the baseline `hribench bench --episodes` times an
// episode against (docs/performance.md, "Measuring").
//
// RawRecording, an EpisodeObserver, records what each physics step of an episode started from,
// as mj_step got it (EpisodeObserver::on_physics_step): the state (time, qpos, qvel and the
// solver's warm start qacc_warmstart) and the inputs (ctrl, the mocap poses, qfrc_applied,
// xfrc_applied). replay() makes the same steps on another mjData: each one's state and inputs
// copied in, then mj_step, nothing else. Between steps an episode may run mj_forward (to observe
// the state after each control step, or when the person grasps something); MuJoCo 2.2.2's
// mj_forward normalises the free bodies' quaternions in qpos and refreshes the warm start, and
// the steps after it depend on that, which is why every step's state is copied rather than
// only the first. Each replayed step is checked: its velocities must be those the episode's
// next step started from (after the last step, the episode's final ones), i.e. the step's
// accelerations bit for bit.
//
// RawAlongside, attached to a later run of the same episode (an episode is deterministic),
// makes the recorded steps of each control step right after it, timed apart from the episode:
// episode and raw alternate every 50 ms and so meet the same machine.

#include <array>
#include <vector>

#include <mujoco/mujoco.h>

#include "eval/episode.h"

namespace hribench::eval {

class RawRecording : public EpisodeObserver {
 public:
  void on_physics_step(const Episode& episode) override;
  void on_end(const Episode& episode) override;

  // Physics steps recorded.
  long steps() const { return steps_; }
  // Makes recorded physics steps [from, to) on `raw` (made for the episode's model, or one
  // compiled the same). Returns the first of them that did not end where the episode's did, or
  // -1. Allocation-free.
  long replay(const mjModel* m, mjData* raw, long from, long to) const;

 private:
  static constexpr size_t kParts = 8;  // qpos, qvel, qacc_warmstart, ctrl, mocap_pos, mocap_quat,
                                       // qfrc_applied, xfrc_applied
  std::array<size_t, kParts> sizes_{};
  size_t stride_ = 0;             // time and the parts
  std::vector<mjtNum> record_;    // per physics step: time, then the parts
  long steps_ = 0;
  std::vector<mjtNum> end_qvel_;  // the episode's velocities at its end
};

class RawAlongside : public EpisodeObserver {
 public:
  // `raw` is made for the episode's model (or one compiled the same) and outlives the run;
  // nothing of it is read before a step's recorded state is copied in, so it needs no reset.
  RawAlongside(const RawRecording& recording, mjData* raw) : recording_(recording), raw_(raw) {}
  void on_physics_step(const Episode&) override { ++steps_; }
  void on_step(const Episode& episode, const StepRecord&) override { catch_up(episode); }
  void on_end(const Episode& episode) override { catch_up(episode); }

  // Wall seconds raw MuJoCo took for the steps made so far.
  double seconds() const { return seconds_; }
  // The first step raw made otherwise than the episode (or the first the recording lacks), or -1.
  long differs() const { return differs_; }

 private:
  void catch_up(const Episode& episode);

  const RawRecording& recording_;
  mjData* raw_;
  long steps_ = 0;     // the episode's physics steps so far
  long replayed_ = 0;  // of them made by raw
  double seconds_ = 0;
  long differs_ = -1;
};

}  // namespace hribench::eval
