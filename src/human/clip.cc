#include "human/clip.h"

#include <algorithm>
#include <cmath>

#include "core/errors.h"

namespace hribench::human {

double Clip::duration() const {
  return frames.empty() ? 0.0 : static_cast<double>(frames.size() - 1) / fps;
}

SkeletonPose Clip::pose_at(double t) const {
  HRIB_CHECK(!frames.empty());
  HRIB_CHECK(fps > 0) << "fps=" << fps;
  const double f = std::clamp(t, 0.0, duration()) * fps;
  const auto i0 = static_cast<size_t>(std::floor(f));
  if (i0 + 1 >= frames.size()) return frames.back();
  const double a = f - static_cast<double>(i0);
  return interpolate(frames[i0], frames[i0 + 1], a);
}

const Phase* Clip::phase(std::string_view name) const {
  for (const Phase& p : phases) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

const Phase* Clip::phase_at(double t) const {
  const Phase* best = nullptr;
  for (const Phase& p : phases) {
    if (t >= p.start && t <= p.end && (best == nullptr || p.end - p.start < best->end - best->start)) {
      best = &p;
    }
  }
  return best;
}

}  // namespace hribench::human
