#pragma once
// A GoogleTest fixture that fails a test on any MuJoCo warning. Two sources are watched:
//  - mju_user_warning: every warning MuJoCo prints (first occurrence per mjData, model
//    compiler warnings, ...) is recorded while the fixture is active;
//  - mjData.warning[i].number: call ExpectNoWarnings(d) on each mjData the test steps (or
//    Watch(d) once; TearDown then checks every watched mjData that is still alive).
//
// Usage:
//   class StepTest : public hribench::testing::MujocoTest {};
//   TEST_F(StepTest, Stable) { ...; Watch(data.mj.get()); ... }

#include <mutex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include "sim/data.h"

namespace hribench::testing {

// Messages MuJoCo sent to mju_user_warning while a MujocoTest was running.
inline std::vector<std::string>& mujoco_warnings() {
  static std::vector<std::string> messages;
  return messages;
}
inline std::mutex& mujoco_warnings_mutex() {
  static std::mutex mutex;
  return mutex;
}
inline void record_mujoco_warning(const char* message) {
  std::lock_guard<std::mutex> lock(mujoco_warnings_mutex());
  mujoco_warnings().emplace_back(message == nullptr ? "(null)" : message);
}

// Names of mjData warning slots with a non-zero count, "" if none.
inline std::string mujoco_warning_counts(const mjData* d) {
  std::ostringstream out;
  for (int i = 0; i < mjNWARNING; ++i) {
    if (d->warning[i].number > 0)
      out << sim::warning_name(i) << " x" << d->warning[i].number << " (info "
          << d->warning[i].lastinfo << ") ";
  }
  return out.str();
}

class MujocoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_ = mju_user_warning;
    {
      std::lock_guard<std::mutex> lock(mujoco_warnings_mutex());
      mujoco_warnings().clear();
    }
    mju_user_warning = &record_mujoco_warning;
  }

  void TearDown() override {
    for (const mjData* d : watched_) ExpectNoWarnings(d);
    mju_user_warning = previous_;
    std::lock_guard<std::mutex> lock(mujoco_warnings_mutex());
    for (const std::string& message : mujoco_warnings())
      ADD_FAILURE() << "MuJoCo warning: " << message;
  }

  // Fails the test if `d` counted any MuJoCo warning.
  static void ExpectNoWarnings(const mjData* d) {
    const std::string counts = mujoco_warning_counts(d);
    EXPECT_TRUE(counts.empty()) << "MuJoCo warnings in mjData: " << counts;
  }

  // Checks `d` at TearDown (it must outlive the test body's end: keep it in the fixture or
  // call Unwatch before freeing it).
  void Watch(const mjData* d) { watched_.push_back(d); }
  void Unwatch(const mjData* d) { std::erase(watched_, d); }

 private:
  void (*previous_)(const char*) = nullptr;
  std::vector<const mjData*> watched_;
};

}  // namespace hribench::testing
