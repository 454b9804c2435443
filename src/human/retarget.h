#pragma once
// Retargeting motion from other skeletons onto ours (human/skeleton.h), and the clip edits a
// script needs to use an imported clip in place of a primitive (time scaling, placement).
//
// Method: a source motion is reduced to world positions of 22 points, one per SMPL joint
// (NameConvention maps source joint names to those points), in our world frame (z up). Each of
// our joints then gets the world rotation that makes its bones point the way the source's do:
//   - pelvis: spine1 direction exact, the right-hip -> left-hip line as close as possible;
//   - spine3: neck direction exact, the right-collar -> left-collar line as close as possible;
//   - every other joint with a child: the child's direction exact, by the smallest rotation
//     from the parent's frame (no added twist);
//   - wrists: toward the hand tip when the source has one, else the forearm's rotation;
//   - head and feet: the parent's rotation.
// Our bone lengths are kept (so they are the same every frame); the root is the source pelvis
// position scaled by (our leg length / source leg length).

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "human/clip.h"
#include "human/skeleton.h"

namespace hribench::human {

// Which world axis is up in a source file.
enum class UpAxis { kAuto, kY, kZ };

struct RetargetOptions {
  std::optional<double> height;      // our skeleton's standing height, m; default: from the
                                     // source's leg length (clamped to [1.0, 2.5])
  std::optional<double> fps;         // overrides the file's frame rate (npy has none: 20)
  std::optional<double> unit_scale;  // metres per file unit (BVH); default: guessed
  UpAxis up = UpAxis::kAuto;
  std::optional<bool> ground;        // shift vertically so the lowest sole touches z = 0;
                                     // default: false (true for SMPL-H npz)
};

// Points of one source frame in our world frame (z up), in any single unit.
struct JointTargets {
  std::array<core::Vec3, kNumJoints> joint{};      // SMPL joint order
  std::array<std::optional<core::Vec3>, 2> hand_tip;  // [left, right] finger direction hint
};

// The proper rotation taking a y-up source frame (x left, y up, z forward: HumanML3D, SMPL,
// CMU BVH) to ours (x forward, y left, z up): (x, y, z) -> (z, x, y); determinant +1.
core::Mat3 y_up_to_z_up();

// Rest-pose description of a 22-joint SMPL-topology skeleton: offset[j] of joint j from its
// parent with every joint frame parallel to the root frame; hand_dir[s] the wrist-to-hand
// direction at rest (left, right).
struct RestTree {
  std::array<core::Vec3, kNumJoints> offset{};
  std::array<core::Vec3, 2> hand_dir{};
};
RestTree rest_tree(const Skeleton& skeleton);

// World rotation of every joint of `tree` whose bones point along `targets` (method above).
std::array<core::Quat, kNumJoints> solve_world_rotations(const RestTree& tree,
                                                         const JointTargets& targets);

// A source naming convention: for each of our 22 joints, a weighted sum of source joints'
// positions (most are a single joint), and optional hand-tip joints.
struct NameConvention {
  std::string name;  // "smpl", "cmu", "cmu_motionbuilder", "mixamo"
  std::array<std::vector<std::pair<std::string, double>>, kNumJoints> joint;
  std::array<std::vector<std::string>, 2> hand_tip;  // first present name wins
};
// Known conventions, most specific first.
const std::vector<NameConvention>& name_conventions();
// Normalised name for matching: lower case, namespace prefix ("mixamorig:") and '_', '-', ' ',
// '.' removed.
std::string normalize_joint_name(std::string_view name);
// The first convention whose required names all occur in `names`; throws core::InputError
// (where = `where`) naming the missing joints of the closest convention otherwise.
const NameConvention& match_convention(const std::vector<std::string>& names, std::string_view where);
// Targets of one frame: world positions of the source's joints (same order as `names`), already
// in our z-up frame.
JointTargets targets_from_named(const NameConvention& convention,
                                const std::vector<std::string>& names,
                                const std::vector<core::Vec3>& positions);

// Source leg length (mean of hip-knee-ankle over both legs) of one frame, in its unit.
double leg_length(const JointTargets& targets);
double leg_length(const Skeleton& skeleton);

// A Clip of our skeleton following `frames` (targets in our z-up frame, any unit). Throws
// core::InputError (where) when frames is empty or fps is not in (0, 1000].
Clip clip_from_targets(const std::vector<JointTargets>& frames, double fps,
                       const RetargetOptions& options, std::string_view where);

// The same motion played `factor` times as long (factor > 1: slower), resampled at the clip's
// own fps; phases scale with it. Requires factor > 0 (else core::InputError).
Clip time_scale(const Clip& clip, double factor);
// The clip moved rigidly in the floor plane so that frame 0's pelvis stands over (x, y) and its
// facing (pelvis x axis projected on the floor) is yaw_rad about +z.
Clip place(const Clip& clip, double x, double y, double yaw_rad);
// Facing yaw of a pose: heading of the pelvis x axis in the floor plane.
double facing_yaw(const SkeletonPose& pose);

}  // namespace hribench::human
