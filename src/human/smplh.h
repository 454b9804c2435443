#pragma once
// SMPL-H parameter files (.npz) as HY-Motion-1.0 and AMASS write them (docs/motion.md):
// `poses` (F, 156) axis-angle in SMPL-H joint order (root first; the first 22 joints are the
// body; 72- and 165-column SMPL / SMPL-X files work too), `trans` (F, 3) metres, optional
// `mocap_framerate` / `mocap_frame_rate` (default 30 fps, HY-Motion's output rate), `betas`
// ignored (no shape blend shapes: the neutral rest skeleton below is used), other members
// (gender, dmpls, Rh, pickled objects) are not decoded.
//
// Import: forward kinematics of the SMPL rest skeleton (zero pose = T-pose; offsets of the
// neutral model, y-up, x = the body's left, z forward; pelvis at J0 + trans), then the joint
// positions are turned into our z-up world with a proper rotation and retargeted by joint
// directions (human/retarget.h).
// Up axis: auto = y-up if the archive has HY-Motion's `Rh`, z-up if it has AMASS's
// `mocap_framerate`, else the axis from pelvis to head in frame 0.

#include <filesystem>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "human/clip.h"
#include "human/npy.h"
#include "human/retarget.h"

namespace hribench::human {

// The neutral SMPL rest skeleton in SMPL's own frame (y up, x left, z forward), metres: joint
// offsets from their parents at zero pose (a T-pose, arms along +-x) and the wrist-to-hand
// directions. J0 (the pelvis at rest) is smpl_pelvis_rest().
RestTree smpl_rest_tree();
core::Vec3 smpl_pelvis_rest();

// World positions of the 22 body joints (and the hand tips) for one frame: root axis-angle
// and 21 local axis-angles (`axis_angle[j]`, SMPL order), root translation `trans`; in the
// file's world frame.
JointTargets smpl_forward_kinematics(const std::array<core::Vec3, kNumJoints>& axis_angle,
                                     const core::Vec3& trans);

// Imports an archive (options.ground defaults to true here: the rest skeleton is not the
// subject's, so the feet are put on the floor). `where` names it in errors.
Clip clip_from_smplh(const NpzArchive& archive, const RetargetOptions& options, std::string_view where);
Clip read_smplh(const std::filesystem::path& path, const RetargetOptions& options);

// An AMASS-style archive of `clip` (z-up): poses (F, 156) float64 with zero hand joints, trans,
// betas zeros(16), mocap_framerate. The SMPL joints point where ours do; the pelvis is placed so
// that importing it with options.height = clip.skeleton.height reproduces our joint positions.
std::string format_smplh(const Clip& clip);

}  // namespace hribench::human
