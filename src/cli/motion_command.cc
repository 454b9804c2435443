// `hribench motion PRIMITIVE|FILE [--param k=v ...] --out clip.json|.npy|.bvh|.npz
//  [--render strip.png]`: generates a primitive (human/motion.h) or imports a motion file
// (human/clip_io.h), optionally time-scales and places it, writes it, and draws a strip of
// evenly spaced frames (an orthographic capsule rendering) so a person can look at it.

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cli/command.h"
#include "core/errors.h"
#include "human/clip_io.h"
#include "human/motion.h"
#include "human/primitives.h"
#include "human/retarget.h"
#include "render/image.h"
#include "render/png.h"

namespace hribench::cli {
namespace {

using core::Vec3;

struct MotionOptions {
  std::string source;
  std::vector<std::string> params;
  std::string out;
  std::string render;
  int render_frames = 6;
  double height = 1.75;
  bool height_given = false;
  double fps = 30;
  bool fps_given = false;
  uint64_t seed = 0;
  std::string place;   // "x,y,yaw_deg"
  double time_scale = 1;
  std::string up = "auto";
  double unit = 0;     // metres per file unit; guessed unless unit_given
  bool unit_given = false;
};

// ---- parameter parsing ----------------------------------------------------------------------

double parse_number(std::string_view text, const std::string& where) {
  double v = 0;
  std::string_view s = text;
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) {
    throw core::InputError(where, "a finite number", fmt::format("'{}'", text));
  }
  return v;
}

std::vector<double> parse_numbers(std::string_view text, size_t count, const std::string& where) {
  std::vector<double> out;
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string_view item = text.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start);
    out.push_back(parse_number(item, where));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (out.size() != count) {
    throw core::InputError(where, fmt::format("{} comma-separated numbers", count), fmt::format("'{}'", text));
  }
  return out;
}

Vec3 parse_point(std::string_view text, const std::string& where) {
  const auto v = parse_numbers(text, 3, where);
  return Vec3(v[0], v[1], v[2]);
}

human::PrimitiveParams primitive_params(const human::PrimitiveInfo& info, const MotionOptions& o,
                                        const Vec3& start, double yaw) {
  human::PrimitiveParams p;
  p.primitive = std::string(info.name);
  p.seed = o.seed;
  for (const std::string& kv : o.params) {
    const size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw core::InputError("--param", "KEY=VALUE", fmt::format("'{}'", kv));
    const std::string key = kv.substr(0, eq);
    const std::string value = kv.substr(eq + 1);
    const human::ParamInfo* param = info.param(key);
    const std::string where = fmt::format("--param {}", key);
    if (param == nullptr) {
      std::string names;
      for (const human::ParamInfo& q : info.params) names += (names.empty() ? "" : ", ") + std::string(q.name);
      throw core::InputError(where, fmt::format("a parameter of {} ({})", info.name, names), fmt::format("'{}'", key));
    }
    switch (param->kind) {
      case human::ParamKind::kNumber: p.numbers[key] = parse_number(value, where); break;
      case human::ParamKind::kSide:
      case human::ParamKind::kChoice: p.choices[key] = value; break;
      case human::ParamKind::kPoint: p.points[key] = parse_point(value, where); break;
      case human::ParamKind::kPoints: {
        std::vector<Vec3> path;
        size_t s = 0;
        while (!value.empty() && s <= value.size()) {
          const size_t semi = value.find(';', s);
          path.push_back(parse_point(value.substr(s, semi == std::string::npos ? std::string::npos : semi - s), where));
          if (semi == std::string::npos) break;
          s = semi + 1;
        }
        p.paths[key] = path;
        break;
      }
      case human::ParamKind::kZone: {
        const auto v = parse_numbers(value, 4, where);
        p.zones[key] = {Vec3(v[0], v[1], v[2]), v[3]};
        break;
      }
      case human::ParamKind::kObject: p.objects[key] = value; break;
    }
  }
  // Demo values for required targets not given, so `hribench motion point` shows something:
  // 0.8 m in front of the person at 1.2 m (zones: 0.5 m in front at 1.0 m).
  const Vec3 ahead(std::cos(yaw), std::sin(yaw), 0);
  for (const human::ParamInfo& q : info.params) {
    if (!q.required) continue;
    const std::string key(q.name);
    if (q.kind == human::ParamKind::kPoint && !p.points.contains(key)) {
      p.points[key] = start + 0.8 * ahead + Vec3(0, 0, 1.2);
    } else if (q.kind == human::ParamKind::kZone && !p.zones.contains(key)) {
      p.zones[key] = {start + 0.5 * ahead + Vec3(0, 0, 1.0), 0.08};
    } else if (q.kind == human::ParamKind::kObject && !p.objects.contains(key)) {
      p.objects[key] = "object";
    }
  }
  return p;
}

// ---- rendering: orthographic capsules -------------------------------------------------------

struct Camera {
  Vec3 forward, right, up;  // unit; forward points into the scene
  Vec3 center;              // world point at the panel centre
  double pixels_per_m;
};

// Colour of a capsule: left side blue, right side orange, head skin, the rest grey.
Vec3 capsule_colour(std::string_view name) {
  if (name.starts_with("left_")) return Vec3(70, 115, 205);
  if (name.starts_with("right_")) return Vec3(220, 120, 55);
  if (name == "head") return Vec3(225, 190, 160);
  return Vec3(165, 165, 170);
}

// Draws one pose into the panel [x0, x0 + w) of `image`, with a floor checker for reference.
void draw_panel(render::Image& image, int x0, int w, const Camera& cam, const human::Skeleton& skeleton,
                const human::SkeletonPose& pose, double progress) {
  const int h = image.height;
  std::vector<double> depth(static_cast<size_t>(w) * static_cast<size_t>(h), 1e300);
  const auto put = [&](int col, int row, const Vec3& c) {
    const size_t i = (static_cast<size_t>(row) * static_cast<size_t>(image.width) + static_cast<size_t>(x0 + col)) * 3;
    for (size_t k = 0; k < 3; ++k) image.rgb[i + k] = static_cast<uint8_t>(std::clamp(c[static_cast<Eigen::Index>(k)], 0.0, 255.0));
  };
  const auto ray_origin = [&](int col, int row) {
    const double sx = (col + 0.5 - w / 2.0) / cam.pixels_per_m;
    const double sy = (h / 2.0 - row - 0.5) / cam.pixels_per_m;
    return Vec3(cam.center + sx * cam.right + sy * cam.up - 20.0 * cam.forward);
  };
  // Capsules in the world, for the floor shadow and the body.
  const auto X = human::forward_kinematics(skeleton, pose);
  struct Segment {
    Vec3 a, b;
    double r;
    Vec3 colour;
  };
  std::vector<Segment> segments;
  for (const human::BodyCapsule& capsule : human::body_capsules(skeleton)) {
    const core::Pose& J = X[static_cast<size_t>(human::index(capsule.joint))];
    segments.push_back({J * capsule.from, J * capsule.to, capsule.radius, capsule_colour(capsule.name)});
  }
  // Is the floor point p straight under a capsule (a vertical shadow)?
  const auto in_shadow = [&](const Vec3& p) {
    for (const Segment& s : segments) {
      const Eigen::Vector2d a = s.a.head<2>(), ab = (s.b - s.a).head<2>(), q = p.head<2>();
      const double len2 = ab.squaredNorm();
      const double t = len2 > 1e-12 ? std::clamp((q - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
      if ((a + t * ab - q).squaredNorm() < s.r * s.r) return true;
    }
    return false;
  };
  // Background and floor (0.5 m checker) with shadows.
  for (int row = 0; row < h; ++row) {
    for (int col = 0; col < w; ++col) {
      const Vec3 o = ray_origin(col, row);
      Vec3 c(245, 245, 250);
      if (cam.forward.z() < -1e-6) {
        const double t = -o.z() / cam.forward.z();
        const Vec3 p = o + t * cam.forward;
        const bool odd = (static_cast<int>(std::floor(p.x() / 0.5)) + static_cast<int>(std::floor(p.y() / 0.5))) % 2 != 0;
        c = odd ? Vec3(200, 205, 200) : Vec3(225, 228, 225);
        if (in_shadow(p)) c *= 0.72;
        depth[static_cast<size_t>(row) * static_cast<size_t>(w) + static_cast<size_t>(col)] = t;
      }
      put(col, row, c);
    }
  }
  // Capsules, z-buffered; shading: Lambert from a light above-left of the camera + ambient.
  const Vec3 light = (-cam.forward + 0.6 * cam.up - 0.4 * cam.right).normalized();
  for (const Segment& seg : segments) {
    const Vec3& a = seg.a;
    const Vec3& b = seg.b;
    const double r = seg.r;
    // Screen bounding box.
    const auto screen = [&](const Vec3& p) {
      const Vec3 d = p - cam.center;
      return std::pair{w / 2.0 + d.dot(cam.right) * cam.pixels_per_m, h / 2.0 - d.dot(cam.up) * cam.pixels_per_m};
    };
    const auto [ax, ay] = screen(a);
    const auto [bx, by] = screen(b);
    const double rp = r * cam.pixels_per_m + 1;
    const int c0 = std::max(0, static_cast<int>(std::floor(std::min(ax, bx) - rp)));
    const int c1 = std::min(w - 1, static_cast<int>(std::ceil(std::max(ax, bx) + rp)));
    const int r0 = std::max(0, static_cast<int>(std::floor(std::min(ay, by) - rp)));
    const int r1 = std::min(h - 1, static_cast<int>(std::ceil(std::max(ay, by) + rp)));
    const Vec3& colour = seg.colour;
    const Vec3 ab = b - a;
    for (int row = r0; row <= r1; ++row) {
      for (int col = c0; col <= c1; ++col) {
        // Closest points between the ray (o + t f) and the segment (a + s ab).
        const Vec3 o = ray_origin(col, row);
        const Vec3& f = cam.forward;
        const Vec3 w0 = o - a;
        const double bb = f.dot(ab), cc = ab.dot(ab), d = f.dot(w0), e = ab.dot(w0);
        const double denom = cc - bb * bb;  // |f| = 1
        double s = denom > 1e-12 ? (e - bb * d) / denom : 0.0;
        s = std::clamp(s, 0.0, cc > 1e-12 ? 1.0 : 0.0);
        const Vec3 q = a + s * ab;
        const double t = (q - o).dot(f);
        const Vec3 on_ray = o + t * f;
        const double dist2 = (on_ray - q).squaredNorm();
        if (dist2 >= r * r) continue;
        const double t_hit = t - std::sqrt(r * r - dist2);
        double& z = depth[static_cast<size_t>(row) * static_cast<size_t>(w) + static_cast<size_t>(col)];
        if (t_hit >= z) continue;
        z = t_hit;
        const Vec3 normal = ((o + t_hit * f) - q).normalized();
        const double shade = 0.35 + 0.65 * std::max(0.0, normal.dot(light));
        put(col, row, colour * shade);
      }
    }
  }
  // Progress bar along the bottom edge, and a separator on the panel's left.
  const int bar = static_cast<int>(std::round(progress * (w - 8)));
  for (int row = h - 6; row < h - 2; ++row) {
    for (int col = 4; col < 4 + bar; ++col) put(col, row, Vec3(90, 90, 100));
  }
  for (int row = 0; row < h; ++row) put(0, row, Vec3(120, 120, 130));
}

void render_strip(const human::Clip& clip, int count, const std::string& path) {
  constexpr int kPanelWidth = 240;
  constexpr int kHeight = 420;
  render::Image image;
  image.resize(kPanelWidth * count, kHeight);
  // View from the front-right of the person's initial facing, 20 degrees above the horizon.
  const double yaw0 = human::facing_yaw(clip.frames.front());
  const double az = yaw0 - core::deg_to_rad(50);
  const double el = core::deg_to_rad(20);
  Camera cam;
  cam.forward = -Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  cam.right = cam.forward.cross(Vec3::UnitZ()).normalized();
  cam.up = cam.right.cross(cam.forward);
  cam.pixels_per_m = kHeight / (clip.skeleton.height + 0.6);
  for (int i = 0; i < count; ++i) {
    const double progress = count > 1 ? static_cast<double>(i) / (count - 1) : 0.0;
    const human::SkeletonPose pose = clip.pose_at(progress * clip.duration());
    const Vec3 pelvis = pose.X_WP.translation;
    cam.center = Vec3(pelvis.x(), pelvis.y(), 0.5 * clip.skeleton.height);
    draw_panel(image, i * kPanelWidth, kPanelWidth, cam, clip.skeleton, pose, progress);
  }
  render::write_png(path, image);
}

// ---- the command ---------------------------------------------------------------------------

bool looks_like_file(const std::string& source) {
  std::string ext = std::filesystem::path(source).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".bvh" || ext == ".npy" || ext == ".npz" || ext == ".json";
}

// Rejects out-of-range flags before any work, so a bad value is one line (exit 2), never an
// internal check failure or an unbounded allocation (frames = duration * fps * time scale).
void check_flags(const MotionOptions& o) {
  if (!(o.fps > 0 && o.fps <= 1000)) {
    throw core::InputError("--fps", "a frame rate in (0, 1000] fps", fmt::format("{}", o.fps));
  }
  if (!(o.time_scale > 0 && o.time_scale <= 100)) {
    throw core::InputError("--time-scale", "a factor in (0, 100]", fmt::format("{}", o.time_scale));
  }
  if (o.unit_given && !(o.unit > 0 && std::isfinite(o.unit))) {
    throw core::InputError("--unit", "a positive number of metres per file unit (e.g. 0.01)",
                           fmt::format("{}", o.unit));
  }
  // The skeleton's own range check, reported against the flag.
  try {
    static_cast<void>(human::Skeleton::FromHeight(o.height));
  } catch (const core::InputError& e) {
    throw core::InputError("--height", e.expected(), fmt::format("{}", o.height));
  }
}

int run_motion(const MotionOptions& o) {
  check_flags(o);
  double x = 0, y = 0, yaw_deg = 0;
  if (!o.place.empty()) {
    const auto v = parse_numbers(o.place, 3, "--place");
    x = v[0];
    y = v[1];
    yaw_deg = v[2];
  }
  if (o.render_frames < 1 || o.render_frames > 24) {
    throw core::InputError("--render-frames", "1 to 24 frames", std::to_string(o.render_frames));
  }
  human::Clip clip;
  if (const human::PrimitiveInfo* info = human::find_primitive(o.source)) {
    const human::Skeleton skeleton = human::Skeleton::FromHeight(o.height);
    const double yaw = core::deg_to_rad(yaw_deg);
    const human::SkeletonPose start = human::SkeletonPose::Standing(skeleton, x, y, yaw);
    clip = human::generate_clip(skeleton, start, primitive_params(*info, o, Vec3(x, y, 0), yaw), o.fps).clip;
  } else if (looks_like_file(o.source)) {
    if (!o.params.empty()) {
      throw core::InputError("--param", "no --param for a motion file (they are primitive parameters)",
                             fmt::format("'{}'", o.params.front()));
    }
    human::RetargetOptions options;
    if (o.height_given) options.height = o.height;
    if (o.fps_given) options.fps = o.fps;
    if (o.unit_given) options.unit_scale = o.unit;
    if (o.up == "y") options.up = human::UpAxis::kY;
    else if (o.up == "z") options.up = human::UpAxis::kZ;
    else if (o.up != "auto") throw core::InputError("--up", "auto, y or z", fmt::format("'{}'", o.up));
    clip = human::read_clip(o.source, options);
    if (!o.place.empty()) clip = human::place(clip, x, y, core::deg_to_rad(yaw_deg));
  } else {
    std::string names;
    for (const human::PrimitiveInfo& p : human::primitive_catalog()) names += (names.empty() ? "" : ", ") + std::string(p.name);
    throw core::InputError("motion", fmt::format("a primitive ({}) or a .bvh/.npy/.npz/.json file", names),
                           fmt::format("'{}'", o.source));
  }
  if (o.time_scale != 1) clip = human::time_scale(clip, o.time_scale);
  human::write_clip(clip, o.out);
  std::string phases;
  for (const human::Phase& p : clip.phases) phases += fmt::format(" {}[{:.2f},{:.2f}]", p.name, p.start, p.end);
  std::printf("wrote %s: %zu frames at %g fps (%.2f s), height %.2f m%s%s\n", o.out.c_str(), clip.frames.size(),
              clip.fps, clip.duration(), clip.skeleton.height, phases.empty() ? "" : ", phases", phases.c_str());
  if (!o.render.empty()) {
    render_strip(clip, o.render_frames, o.render);
    std::printf("rendered %d frames to %s\n", o.render_frames, o.render.c_str());
  }
  return 0;
}

HRIB_REGISTER_COMMAND(
    "motion", "Generate a primitive or import a motion file, write it, optionally render a strip",
    [](CLI::App& app) -> std::function<int()> {
      auto o = std::make_shared<MotionOptions>();
      app.add_option("source", o->source, "primitive name (point, reach, ...) or motion file (.bvh .npy .npz .json)")
          ->required();
      app.add_option("--param", o->params, "primitive parameter KEY=VALUE (points: x,y,z; zones: x,y,z,r; "
                                           "paths: x,y,z;x,y,z); repeatable");
      app.add_option("--out", o->out, "clip file to write: .json, .bvh, .npy (+ .npy.json) or .npz")->required();
      app.add_option("--render", o->render, "PNG strip of evenly spaced frames");
      app.add_option("--render-frames", o->render_frames, "frames in the strip")->capture_default_str();
      app.add_option("--height", o->height, "person height, m (primitives; files: default from the source)")
          ->capture_default_str()->each([o](const std::string&) { o->height_given = true; });
      app.add_option("--fps", o->fps, "frame rate (primitives; files: overrides the file's)")
          ->capture_default_str()->each([o](const std::string&) { o->fps_given = true; });
      app.add_option("--seed", o->seed, "seed of tremor phases (primitives)")->capture_default_str();
      app.add_option("--place", o->place, "x,y,yaw_deg: start (primitives) or placement (files) in the world");
      app.add_option("--time-scale", o->time_scale, "play the clip this many times as long")->capture_default_str();
      app.add_option("--up", o->up, "files: up axis auto, y or z")->capture_default_str();
      app.add_option("--unit", o->unit, "BVH: metres per file unit, e.g. 0.01 for cm (default: guessed)")
          ->each([o](const std::string&) { o->unit_given = true; });
      app.footer([] {
        std::string names;
        for (const human::PrimitiveInfo& p : human::primitive_catalog()) {
          names += (names.empty() ? "" : ", ") + std::string(p.name);
        }
        return "Primitives: " + names + " (docs/motion.md).";
      });
      return [o] { return run_motion(*o); };
    });

}  // namespace
}  // namespace hribench::cli
