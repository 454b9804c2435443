#pragma once
// Hand-built EpisodeLogs for the eval tests: a robot whose end effector follows a given path,
// predicate series switched on and off by time, events, separation and contacts.

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "eval/episode_log.h"

namespace hribench::eval::testing {

class EpisodeBuilder {
 public:
  // Steps at k * dt for k = 0 .. duration / dt; the end effector rests at (0.4, 0, 1.0), the
  // gripper is open, no human nearby; every predicate series is false.
  explicit EpisodeBuilder(double duration, std::vector<std::string> predicates = {"success"},
                          double dt = 0.05) {
    log_.task = "test_task";
    log_.role = "instructor";
    log_.spec_hash = "0123abcd";
    log_.seed = 7;
    log_.policy = "noop";
    log_.robot = "panda";
    log_.horizon = duration;
    log_.control_dt = dt;
    log_.object_names = {"cube", "bin"};
    log_.predicate_names = std::move(predicates);
    const int n = static_cast<int>(std::lround(duration / dt));
    for (int k = 0; k <= n; ++k) {
      StepRecord s;
      s.time = k * dt;
      s.joint_pos = {0, -0.3, 0, -2.2, 0, 1.9, 0.8};
      s.X_WT.translation = core::Vec3(0.4, 0, 1.0);
      s.gripper_width = 0.08;
      s.gripper_target = 0.08;
      s.object_poses.resize(2);
      s.lid_angles.assign(2, 0.0);
      s.separation = std::numeric_limits<double>::infinity();
      s.predicates.assign(log_.predicate_names.size(), 0);
      log_.steps.push_back(s);
    }
  }

  // The end effector moves along +x at `speed` m/s during [from, to] (position continuous).
  EpisodeBuilder& move_x(double from, double to, double speed) {
    for (StepRecord& s : log_.steps) {
      const double t = std::min(std::max(s.time, from), to);
      if (s.time > from) s.X_WT.translation.x() += speed * (t - from);
    }
    return *this;
  }
  // The gripper width changes at `rate` m/s during [from, to], commanded to where it ends (the
  // opening it is told over the steps after `from`, up to `to`).
  EpisodeBuilder& grip(double from, double to, double rate) {
    for (StepRecord& s : log_.steps) {
      const double t = std::min(std::max(s.time, from), to);
      if (s.time > from) s.gripper_width += rate * (t - from);
    }
    double end = 0;
    for (const StepRecord& s : log_.steps) {
      if (s.time <= to + 1e-9) end = s.gripper_width;
    }
    for (StepRecord& s : log_.steps) {
      if (s.time > from + 1e-9 && s.time <= to + 1e-9) s.gripper_target = end;
    }
    return *this;
  }
  // The width from the step at `time` on, and the opening commanded over the interval that
  // ends there and after it.
  EpisodeBuilder& gripper_at(double time, double width, double target) {
    for (StepRecord& s : log_.steps) {
      if (s.time >= time - 1e-9) {
        s.gripper_width = width;
        s.gripper_target = target;
      }
    }
    return *this;
  }
  // The opening commanded over the intervals that end at the steps with from < t <= to.
  EpisodeBuilder& gripper_target(double from, double to, double target) {
    for (StepRecord& s : log_.steps) {
      if (s.time > from + 1e-9 && s.time <= to + 1e-9) s.gripper_target = target;
    }
    return *this;
  }
  // Predicate `name` takes `value` at the steps with from <= t <= to (+- 1e-9).
  EpisodeBuilder& predicate(const std::string& name, double from, double to, bool value = true) {
    const auto index = log_.predicate_index(name);
    for (StepRecord& s : log_.steps) {
      if (s.time >= from - 1e-9 && s.time <= to + 1e-9) s.predicates[*index] = value ? 1 : 0;
    }
    return *this;
  }
  EpisodeBuilder& event(double time, const std::string& name, EventKind kind = EventKind::kPhase,
                        Actor actor = Actor::kHuman) {
    log_.events.push_back(Event{time, kind, actor, name, ""});
    std::stable_sort(log_.events.begin(), log_.events.end(),
                     [](const Event& a, const Event& b) { return a.time < b.time; });
    return *this;
  }
  // Separation and closest-point speeds at the steps with from <= t <= to.
  EpisodeBuilder& separation(double from, double to, double d, double approach = 0,
                             double speed = 0) {
    for (StepRecord& s : log_.steps) {
      if (s.time >= from - 1e-9 && s.time <= to + 1e-9) {
        s.separation = d;
        s.approach_speed = approach;
        s.closest_point_speed = speed;
      }
    }
    return *this;
  }
  EpisodeBuilder& contact(double from, double to, const Contact& c) {
    for (StepRecord& s : log_.steps) {
      if (s.time >= from - 1e-9 && s.time <= to + 1e-9) s.contacts.push_back(c);
    }
    return *this;
  }
  EpisodeBuilder& status(core::EpisodeStatus status, std::string reason) {
    log_.status = status;
    log_.status_reason = std::move(reason);
    return *this;
  }
  const EpisodeLog& log() const { return log_; }

 private:
  EpisodeLog log_;
};

inline Contact human_contact(const std::string& part, human::BodyRegion region, double force,
                             bool finger = true) {
  return Contact{finger ? "left_finger_pad" : "panda_link5", finger, ContactOther::kHuman, part,
                 region, force};
}

}  // namespace hribench::eval::testing
