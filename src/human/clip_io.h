#pragma once
// Reading and writing clips, chosen by file extension:
//   .json  our clip format (below), exact;
//   .bvh   BVH (human/bvh.h), read with retargeting, written as our 22-joint hierarchy;
//   .npy   HumanML3D joint positions (F, 22, 3), y-up (x left, y up, z forward), metres,
//          float32 or float64; 20 fps unless a sidecar "<file>.npy.json" {"fps": N} says
//          otherwise (the writer always writes one);
//   .npz   SMPL-H parameters (human/smplh.h), AMASS layout, z-up.
//
// clip.json (version 1):
//   {"format": "hribench.clip", "version": 1,
//    "skeleton": {"height": 1.75},            // Skeleton::FromHeight(height)
//    "fps": 30, "active_hand": "left" | "right" | null,
//    "phases": [{"name": "stroke", "start": 0.4, "end": 0.9}, ...],   // seconds
//    "joints": ["pelvis", ..., "right_wrist"],                         // order of "local"
//    "frames": [{"root": {"p": [x, y, z], "q": [w, x, y, z]},          // X_WP, world z-up, m
//                "local": [[w, x, y, z] x 22]}, ...]}                  // local[pelvis] = identity

#include <filesystem>
#include <string>
#include <string_view>

#include "human/clip.h"
#include "human/retarget.h"

namespace hribench::human {

std::string format_clip_json(const Clip& clip);
// Throws core::InputError naming the file and the JSON key path ("frames[3].local[2]").
Clip parse_clip_json(std::string_view text, std::string_view where);

// HumanML3D joint file bytes of `clip` (float32, y-up, at the clip's fps).
std::string format_humanml3d(const Clip& clip);
Clip parse_humanml3d(std::string_view npy_bytes, double fps, const RetargetOptions& options,
                     std::string_view where);

// Reads any supported file (by extension, case-insensitive). Throws core::InputError.
Clip read_clip(const std::filesystem::path& path, const RetargetOptions& options = {});
// Writes .json, .bvh (ZYX channels), .npy (+ .npy.json sidecar) or .npz. Throws
// core::InputError for an unknown extension or a file that cannot be written.
void write_clip(const Clip& clip, const std::filesystem::path& path);

}  // namespace hribench::human
