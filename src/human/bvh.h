#pragma once
// Biovision Hierarchy (BVH) motion files (docs/motion.md): a parser that keeps the file's
// own joints, axes and units, forward kinematics on it, a formatter, and conversion to and from
// our Clip (through human/retarget.h).
//
// Grammar accepted: HIERARCHY, one or more ROOT trees of JOINT / End Site blocks with OFFSET and
// CHANNELS (any subset and order of X/Y/Zposition and X/Y/Zrotation), then MOTION, Frames: N,
// Frame Time: dt and N lines of values in depth-first channel order. Keywords are
// case-insensitive; lines may end in LF, CRLF or CR; a joint name of several words is joined
// with '_'. Errors are core::InputError with where = "FILE:LINE".

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "core/math.h"
#include "human/clip.h"
#include "human/retarget.h"

namespace hribench::human {

enum class BvhChannel { kXposition, kYposition, kZposition, kXrotation, kYrotation, kZrotation };
std::string_view to_string(BvhChannel channel);  // "Xposition", ...

struct BvhJoint {
  std::string name;
  int parent = -1;               // index into BvhMotion::joints, -1 for a ROOT
  core::Vec3 offset = core::Vec3::Zero();  // from the parent joint, file units and axes
  std::vector<BvhChannel> channels;
  size_t first_channel = 0;      // column of channels[0] in a frame's values
  bool has_end_site = false;
  core::Vec3 end_site = core::Vec3::Zero();  // End Site OFFSET (first one), if has_end_site
};

struct BvhMotion {
  std::vector<BvhJoint> joints;  // depth-first declaration order: parents before children
  size_t num_channels = 0;       // values per frame
  double frame_time = 0;         // seconds, > 0
  std::vector<std::vector<double>> frames;  // frames[f][c]: positions in file units, degrees
};

// Parses BVH text; `name` (the file name) prefixes error positions.
BvhMotion parse_bvh(std::string_view text, std::string_view name);
// Reads and parses a file. Throws core::InputError (cannot open, malformed).
BvhMotion read_bvh(const std::filesystem::path& path);
// BVH text of `motion` (tabs for indentation, LF line ends, 6 decimals in positions and angles).
std::string format_bvh(const BvhMotion& motion);

// Frames per second of a frame time; rounds to the nearest integer within 0.1% (BVH files store
// truncated frame times such as .0083333 for 120 fps).
double bvh_fps(double frame_time);

// Local rotation of one joint at one frame: the product of its rotation channels in listed
// order, R = R(c1) R(c2) R(c3) (column vectors, degrees).
core::Quat bvh_local_rotation(const BvhMotion& motion, size_t joint, size_t frame);
// World pose of every joint at frame `frame`, in file units and axes: X_W,joint =
// X_W,parent * (OFFSET + position channels, rotation channels).
std::vector<core::Pose> bvh_forward_kinematics(const BvhMotion& motion, size_t frame);

// Rotation order written by bvh_from_clip.
enum class BvhRotationOrder { kZYX, kXYZ };

// Imports a BVH motion onto our skeleton: names are matched against the known conventions
// (human/retarget.h), the up axis (auto: the axis from hips to head in frame 0) is turned to
// our z-up, the unit is guessed (metres, centimetres, inches, CMU units x 0.056444, mm) unless
// options.unit_scale is set, and the motion is retargeted by joint directions. `where` names
// the source in errors.
Clip clip_from_bvh(const BvhMotion& motion, const RetargetOptions& options, std::string_view where);

// Our 22-joint hierarchy (SMPL names) as BVH: y-up (x left, y up, z forward, as HumanML3D and
// CMU), centimetres, root `pelvis` with Xposition Yposition Zposition + 3 rotation channels,
// every other joint 3 rotation channels in `order`; End Sites at the head (crown), wrists
// (finger tips) and feet (toe tips).
BvhMotion bvh_from_clip(const Clip& clip, BvhRotationOrder order);

}  // namespace hribench::human
