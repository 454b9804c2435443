#pragma once
// A timed human motion: a sequence of skeleton poses at a fixed frame rate, with named phases
// and per-frame labels. Procedural primitives, importers (BVH, HumanML3D npy, SMPL-H npz) and
// writers all meet in this type.

#include <optional>
#include <string>
#include <vector>

#include "human/skeleton.h"

namespace hribench::human {

// A named interval of a motion, e.g. point's "stroke" or offer's "hold_stable". Seconds from
// the start of the clip; start <= end.
struct Phase {
  std::string name;
  double start = 0;
  double end = 0;
};

struct Clip {
  Skeleton skeleton;
  double fps = 30;                    // frames per second, > 0
  std::vector<SkeletonPose> frames;   // frame i is at time i / fps
  std::vector<Phase> phases;          // in start order; may overlap only when nested
  std::optional<Side> active_hand;    // the hand the motion is about, if any

  double duration() const;            // (frames - 1) / fps, 0 for an empty clip
  // The pose at time t (seconds, clamped to [0, duration]): root and local rotations
  // interpolated between the two nearest frames (lerp / slerp). Requires frames non-empty.
  SkeletonPose pose_at(double t) const;
  // The phase with this name, if the clip has it.
  const Phase* phase(std::string_view name) const;
  // The innermost phase containing t, if any.
  const Phase* phase_at(double t) const;
};

}  // namespace hribench::human
