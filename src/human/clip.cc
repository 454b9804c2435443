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
  const SkeletonPose& p0 = frames[i0];
  const SkeletonPose& p1 = frames[i0 + 1];
  SkeletonPose out;
  out.X_WP.translation = (1 - a) * p0.X_WP.translation + a * p1.X_WP.translation;
  out.X_WP.rotation = p0.X_WP.rotation.slerp(a, p1.X_WP.rotation);
  for (size_t j = 0; j < out.local.size(); ++j) out.local[j] = p0.local[j].slerp(a, p1.local[j]);
  for (size_t h = 0; h < out.hands.size(); ++h) {
    out.hands[h] = {(1 - a) * p0.hands[h].grip + a * p1.hands[h].grip,
                    (1 - a) * p0.hands[h].point + a * p1.hands[h].point};
  }
  return out;
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
