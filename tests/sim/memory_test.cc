#include "sim/memory.h"

#include <cstdint>
#include <cstring>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include "model/model.h"
#include "sim/control.h"
#include "sim/data.h"
#include "support/mujoco_fixture.h"

namespace hribench::sim {
namespace {

using MemoryTest = testing::MujocoTest;

bool aligned(const void* p) { return reinterpret_cast<std::uintptr_t>(p) % 64 == 0; }

TEST_F(MemoryTest, AFreedStateIsHandedToTheNextDataOfTheModel) {
  keep_large_allocations();
  const model::Model model = model::build(model::SceneSpec::Default());
  mjData* first = mj_makeData(model.m());
  void* buffer = first->buffer;
  void* stack = first->stack;
  EXPECT_GE(static_cast<size_t>(first->nbuffer), kLargeBlockBytes);  // the arena makes it large
  mj_deleteData(first);
  EXPECT_GE(kept_blocks(), 2u);
  mjData* second = mj_makeData(model.m());
  EXPECT_EQ(second->buffer, buffer);
  EXPECT_EQ(second->stack, stack);
  mj_deleteData(second);
}

TEST_F(MemoryTest, ReusedMemoryComputesTheSameToTheBit) {
  keep_large_allocations();
  const model::Model model = model::build(model::SceneSpec::Default());
  // The arm driven away from home for a second: contacts, constraint rows and the stack in use.
  const auto run = [&](std::vector<mjtNum>& state, const void*& buffer) {
    Data data = make_data(model);
    buffer = data.mj->buffer;
    ArmVector q = model.robot.home();
    q[1] += 0.4;
    q[3] += 0.3;
    set_joint_targets(model, data, q);
    for (int i = 0; i < 200; ++i) step(model, data);
    ExpectNoWarnings(data.mj.get());
    const mjData* d = data.mj.get();
    state.assign(d->qpos, d->qpos + model.m()->nq);
    state.insert(state.end(), d->qvel, d->qvel + model.m()->nv);
    state.insert(state.end(), d->qacc_warmstart, d->qacc_warmstart + model.m()->nv);
  };
  std::vector<mjtNum> first, second;
  const void* first_buffer = nullptr;
  const void* second_buffer = nullptr;
  run(first, first_buffer);
  run(second, second_buffer);
  EXPECT_EQ(second_buffer, first_buffer);  // the second ran on the first's memory
  ASSERT_EQ(first.size(), second.size());
  EXPECT_EQ(std::memcmp(first.data(), second.data(), first.size() * sizeof(mjtNum)), 0);
}

TEST_F(MemoryTest, KeepsAtMostItsCountAndAlignsAsMuJoCoDoes) {
  keep_large_allocations();
  std::vector<void*> blocks;
  const size_t n = max_kept_blocks() + 3;
  for (size_t i = 0; i < n; ++i) {  // all held at once, then all freed
    blocks.push_back(mju_malloc(kLargeBlockBytes + 1));
    EXPECT_TRUE(aligned(blocks.back()));
  }
  for (void* p : blocks) mju_free(p);
  EXPECT_EQ(kept_blocks(), max_kept_blocks());
  EXPECT_GE(kept_bytes(), max_kept_blocks() * kLargeBlockBytes);
  void* small = mju_malloc(100);
  EXPECT_TRUE(aligned(small));
  mju_free(small);
  EXPECT_EQ(kept_blocks(), max_kept_blocks());  // small blocks are not kept
}

TEST_F(MemoryTest, WorkersMakingAndFreeingDataAtOnceComputeTheSame) {
  keep_large_allocations();
  const model::Model model = model::build(model::SceneSpec::Default());
  const auto final_qpos = [&] {
    Data data = make_data(model);
    for (int i = 0; i < 50; ++i) step(model, data);
    return std::vector<mjtNum>(data.mj->qpos, data.mj->qpos + model.m()->nq);
  };
  const std::vector<mjtNum> expected = final_qpos();
  std::vector<int> same(4, 0);
  std::vector<std::thread> workers;
  for (size_t w = 0; w < same.size(); ++w) {
    workers.emplace_back([&, w] {
      for (int i = 0; i < 5; ++i) same[w] += final_qpos() == expected ? 1 : 0;
    });
  }
  for (std::thread& t : workers) t.join();
  for (const int n : same) EXPECT_EQ(n, 5);
  EXPECT_LE(kept_blocks(), max_kept_blocks());
}

}  // namespace
}  // namespace hribench::sim
