#include "eval/raw_replay.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cstring>

namespace hribench::eval {
namespace {

// The arrays a physics step starts from, in the record's order (RawRecording::kParts):
// qpos, qvel, qacc_warmstart, ctrl, mocap_pos, mocap_quat, qfrc_applied, xfrc_applied.
template <class MjData>
auto parts_of(MjData* d) {
  return std::array{d->qpos, d->qvel, d->qacc_warmstart, d->ctrl, d->mocap_pos, d->mocap_quat,
                    d->qfrc_applied, d->xfrc_applied};
}

}  // namespace

void RawRecording::on_physics_step(const Episode& episode) {
  const mjModel& m = *episode.model().m();
  const mjData* d = episode.data().mj.get();
  if (steps_ == 0) {
    sizes_ = {static_cast<size_t>(m.nq), static_cast<size_t>(m.nv),         static_cast<size_t>(m.nv),
              static_cast<size_t>(m.nu), static_cast<size_t>(3 * m.nmocap), static_cast<size_t>(4 * m.nmocap),
              static_cast<size_t>(m.nv), static_cast<size_t>(6 * m.nbody)};
    stride_ = 1;
    for (const size_t n : sizes_) stride_ += n;
  }
  const auto from = parts_of(d);
  static_assert(from.size() == kParts);
  record_.push_back(d->time);
  for (size_t i = 0; i < kParts; ++i) record_.insert(record_.end(), from[i], from[i] + sizes_[i]);
  ++steps_;
}

void RawRecording::on_end(const Episode& episode) {
  const mjData* d = episode.data().mj.get();
  end_qvel_.assign(d->qvel, d->qvel + episode.model().m()->nv);
}

long RawRecording::replay(const mjModel* m, mjData* raw, long from, long to) const {
  const auto into = parts_of(raw);
  const size_t nv = sizes_[1];
  long differs = -1;
  for (long k = std::max(from, 0L); k < std::min(to, steps_); ++k) {
    const mjtNum* in = record_.data() + static_cast<size_t>(k) * stride_;
    raw->time = *in++;
    for (size_t i = 0; i < kParts; ++i) {
      std::memcpy(into[i], in, sizeof(mjtNum) * sizes_[i]);
      in += sizes_[i];
    }
    mj_step(m, raw);
    // The next step's qvel, one past its time and qpos; after the last, the episode's end.
    const mjtNum* next = k + 1 < steps_ ? in + 1 + sizes_[0] : end_qvel_.data();
    const bool known = k + 1 < steps_ || end_qvel_.size() == nv;
    if (differs < 0 && known && std::memcmp(raw->qvel, next, sizeof(mjtNum) * nv) != 0) differs = k;
  }
  return differs;
}

void RawAlongside::catch_up(const Episode& episode) {
  if (replayed_ == steps_) return;
  const long to = std::min(steps_, recording_.steps());
  const auto start = std::chrono::steady_clock::now();
  const long differs = recording_.replay(episode.model().m(), raw_, replayed_, to);
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (differs_ < 0) differs_ = differs;
  if (differs_ < 0 && to < steps_) differs_ = to;  // the episode ran past the recording
  replayed_ = steps_;
}

}  // namespace hribench::eval
