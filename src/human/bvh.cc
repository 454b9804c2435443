#include "human/bvh.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>
#include <unordered_set>

#include <fmt/format.h>

#include "core/errors.h"
#include "core/limits.h"

namespace hribench::human {
namespace {

using core::Quat;
using core::Vec3;

struct Token {
  std::string_view text;
  int line;
};

// Whitespace-separated tokens with 1-based line numbers; '{' and '}' are tokens of their own.
// LF, CRLF and CR each end a line.
std::vector<Token> tokenize(std::string_view text) {
  std::vector<Token> tokens;
  int line = 1;
  size_t i = 0;
  const auto is_space = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v';
  };
  while (i < text.size()) {
    const char c = text[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (c == '\r') {
      ++line;
      i += (i + 1 < text.size() && text[i + 1] == '\n') ? 2 : 1;
    } else if (is_space(c)) {
      ++i;
    } else if (c == '{' || c == '}') {
      tokens.push_back({text.substr(i, 1), line});
      ++i;
    } else {
      const size_t start = i;
      while (i < text.size() && !is_space(text[i]) && text[i] != '{' && text[i] != '}') ++i;
      tokens.push_back({text.substr(start, i - start), line});
    }
  }
  return tokens;
}

bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() &&
         std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

std::optional<double> parse_double(std::string_view s) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return value;
}

std::string quote_token(std::string_view s) { return fmt::format("'{}'", s); }

constexpr std::array<std::string_view, 6> kChannelNames = {
    "Xposition", "Yposition", "Zposition", "Xrotation", "Yrotation", "Zrotation"};

class Parser {
 public:
  Parser(std::string_view text, std::string_view name) : tokens_(tokenize(text)), name_(name) {}

  BvhMotion parse() {
    expect_keyword("HIERARCHY");
    while (pos_ < tokens_.size() && iequals(peek().text, "ROOT")) {
      ++pos_;
      parse_joint(-1, 1);
    }
    if (motion_.joints.empty()) fail(peek_line(), "ROOT", peek_text());
    expect_keyword("MOTION");
    parse_header_number("Frames");
    const Token frames_token = next("the number of frames after 'Frames:'");
    int num_frames = 0;
    const auto [end, ec] = std::from_chars(frames_token.text.data(),
                                           frames_token.text.data() + frames_token.text.size(),
                                           num_frames);
    if (ec != std::errc() || end != frames_token.text.data() + frames_token.text.size() ||
        num_frames < 1 || num_frames > 10'000'000) {
      fail(frames_token.line, "a frame count from 1 to 10000000 after 'Frames:'",
           quote_token(frames_token.text));
    }
    const int frames_line = frames_token.line;
    {
      const int line = peek_line();
      const std::string got = peek_text();
      if (!iequals(next("'Frame Time:'").text, "Frame")) fail(line, "'Frame Time:'", got);
    }
    parse_header_number("Time");
    const Token dt_token = next("the frame time in seconds after 'Frame Time:'");
    const auto dt = parse_double(dt_token.text);
    if (!dt || !std::isfinite(*dt) || *dt <= 0) {
      fail(dt_token.line, "a positive frame time in seconds", quote_token(dt_token.text));
    }
    if (*dt < 1e-3 || *dt > 1.0) {
      fail(dt_token.line, "a frame time giving 1 to 1000 frames per second",
           fmt::format("{} s ({:.6g} fps)", dt_token.text, 1.0 / *dt));
    }
    motion_.frame_time = *dt;
    if (motion_.num_channels == 0) fail(dt_token.line, "a hierarchy with at least one channel", "none");
    parse_frames(static_cast<size_t>(num_frames), frames_line, dt_token.line);
    return std::move(motion_);
  }

 private:
  [[noreturn]] void fail(int line, std::string expected, std::string got) const {
    throw core::InputError(fmt::format("{}:{}", name_, line), std::move(expected), std::move(got));
  }
  const Token& peek() const {
    static const Token kEnd{"end of file", 0};
    return pos_ < tokens_.size() ? tokens_[pos_] : kEnd;
  }
  int peek_line() const {
    if (pos_ < tokens_.size()) return tokens_[pos_].line;
    return tokens_.empty() ? 1 : tokens_.back().line;
  }
  std::string peek_text() const {
    return pos_ < tokens_.size() ? quote_token(tokens_[pos_].text) : "end of file";
  }
  Token next(std::string_view expected) {
    if (pos_ >= tokens_.size()) fail(peek_line(), std::string(expected), "end of file");
    return tokens_[pos_++];
  }
  void expect_keyword(std::string_view keyword) {
    const int line = peek_line();
    const std::string got = peek_text();
    const Token t = next(std::string(keyword));
    if (!iequals(t.text, keyword)) fail(line, std::string(keyword), got);
  }
  // "Frames:" / "Frames :" / "Time:" / "Time :".
  void parse_header_number(std::string_view keyword) {
    const int line = peek_line();
    const std::string got = peek_text();
    const std::string expected = fmt::format("'{}:'", keyword);
    const Token t = next(expected);
    if (iequals(t.text, std::string(keyword) + ":")) return;
    if (iequals(t.text, keyword) && pos_ < tokens_.size() && tokens_[pos_].text == ":") {
      ++pos_;
      return;
    }
    fail(line, expected, got);
  }
  double number(std::string_view what) {
    const int line = peek_line();
    const std::string got = peek_text();
    const Token t = next(what);
    const auto v = parse_double(t.text);
    if (!v) fail(line, std::string(what), got);
    if (!std::isfinite(*v)) fail(line, fmt::format("a finite {}", what.substr(2)), got);
    return *v;
  }
  Vec3 offset() {
    expect_keyword("OFFSET");
    const double x = number("a number (OFFSET x)");
    const double y = number("a number (OFFSET y)");
    const double z = number("a number (OFFSET z)");
    return Vec3(x, y, z);
  }
  bool is_block_keyword(std::string_view t) const {
    return t == "{" || t == "}" || iequals(t, "OFFSET") || iequals(t, "CHANNELS") ||
           iequals(t, "JOINT") || iequals(t, "ROOT") || iequals(t, "MOTION");
  }
  // Name tokens up to '{', joined with '_'.
  std::string block_name(int keyword_line, bool required) {
    std::string name;
    while (pos_ < tokens_.size() && !is_block_keyword(tokens_[pos_].text)) {
      if (!name.empty()) name += '_';
      name += tokens_[pos_++].text;
    }
    if (required && name.empty()) fail(keyword_line, "a joint name", peek_text());
    const int line = peek_line();
    const std::string got = peek_text();
    if (pos_ >= tokens_.size() || tokens_[pos_].text != "{") fail(line, "'{'", got);
    ++pos_;
    return name;
  }
  // A ROOT (depth 1) or JOINT block; nested JOINTs recurse, at most core::kMaxNestingDepth deep.
  void parse_joint(int parent, int depth) {
    const int keyword_line = tokens_[pos_ - 1].line;
    if (depth > core::kMaxNestingDepth) {
      fail(keyword_line, fmt::format("joints nested at most {} deep", core::kMaxNestingDepth), "deeper nesting");
    }
    BvhJoint joint;
    joint.name = block_name(keyword_line, true);
    joint.parent = parent;
    if (!names_.insert(joint.name).second) {
      fail(keyword_line, "unique joint names", fmt::format("a second joint {}", quote_token(joint.name)));
    }
    joint.offset = offset();
    if (pos_ < tokens_.size() && iequals(tokens_[pos_].text, "CHANNELS")) {
      const int line = tokens_[pos_].line;
      ++pos_;
      const Token n_token = next("the channel count after CHANNELS");
      int n = -1;
      std::from_chars(n_token.text.data(), n_token.text.data() + n_token.text.size(), n);
      if (n < 0 || n > 6 || std::to_string(n) != n_token.text) {
        fail(line, "a channel count from 0 to 6", quote_token(n_token.text));
      }
      for (int k = 0; k < n; ++k) {
        const int cline = peek_line();
        const std::string got = peek_text();
        const Token c = next("a channel name");
        auto it = std::find_if(kChannelNames.begin(), kChannelNames.end(),
                               [&](std::string_view known) { return iequals(known, c.text); });
        if (it == kChannelNames.end()) {
          fail(cline,
               fmt::format("channel {} of {}: Xposition, Yposition, Zposition, Xrotation, "
                           "Yrotation or Zrotation", k + 1, n),
               got);
        }
        const auto channel = static_cast<BvhChannel>(it - kChannelNames.begin());
        if (std::find(joint.channels.begin(), joint.channels.end(), channel) != joint.channels.end()) {
          fail(cline, "each channel once per joint", fmt::format("{} twice", *it));
        }
        joint.channels.push_back(channel);
      }
    }
    joint.first_channel = motion_.num_channels;
    motion_.num_channels += joint.channels.size();
    const int index = static_cast<int>(motion_.joints.size());
    motion_.joints.push_back(std::move(joint));
    while (true) {
      const int line = peek_line();
      const std::string got = peek_text();
      const Token t = next("JOINT, End Site or '}'");
      if (iequals(t.text, "JOINT")) {
        parse_joint(index, depth + 1);
      } else if (iequals(t.text, "End")) {
        const int site_line = peek_line();
        const std::string site_got = peek_text();
        const Token site = next("'Site' after 'End'");
        if (!iequals(site.text, "Site")) fail(site_line, "'Site' after 'End'", site_got);
        block_name(line, false);
        const Vec3 end = offset();
        const int close_line = peek_line();
        const std::string close_got = peek_text();
        if (next("'}' closing End Site").text != "}") fail(close_line, "'}' closing End Site", close_got);
        BvhJoint& j = motion_.joints[static_cast<size_t>(index)];
        if (!j.has_end_site) {
          j.has_end_site = true;
          j.end_site = end;
        }
      } else if (t.text == "}") {
        return;
      } else {
        fail(line, "JOINT, End Site or '}'", got);
      }
    }
  }
  void parse_frames(size_t num_frames, int frames_line, int header_line) {
    // Reserved only for the frames the remaining tokens can hold, not the count the file declares.
    motion_.frames.reserve(std::min(num_frames, (tokens_.size() - pos_) / motion_.num_channels + 1));
    while (pos_ < tokens_.size()) {
      const int line = tokens_[pos_].line;
      size_t end = pos_;
      while (end < tokens_.size() && tokens_[end].line == line) ++end;
      const size_t count = end - pos_;
      if (motion_.frames.size() == num_frames) {
        fail(line, fmt::format("{} frames (Frames: at line {})", num_frames, frames_line),
             "more frame lines");
      }
      if (line == header_line) fail(line, "frame values on the lines after 'Frame Time:'", peek_text());
      if (count != motion_.num_channels) {
        fail(line,
             fmt::format("{} values in frame {} (one per channel)", motion_.num_channels,
                         motion_.frames.size() + 1),
             std::to_string(count));
      }
      std::vector<double> values(count);
      for (size_t k = 0; k < count; ++k) {
        const auto v = parse_double(tokens_[pos_ + k].text);
        if (!v || !std::isfinite(*v)) {
          fail(line, fmt::format("a finite number (value {} of frame {})", k + 1,
                                 motion_.frames.size() + 1),
               quote_token(tokens_[pos_ + k].text));
        }
        values[k] = *v;
      }
      motion_.frames.push_back(std::move(values));
      pos_ = end;
    }
    if (motion_.frames.size() != num_frames) {
      fail(peek_line(), fmt::format("{} frames (Frames: at line {})", num_frames, frames_line),
           fmt::format("{} (the file ends)", motion_.frames.size()));
    }
  }

  std::vector<Token> tokens_;
  std::string_view name_;
  size_t pos_ = 0;
  BvhMotion motion_;
  std::unordered_set<std::string> names_;  // joint names so far
};

Vec3 axis_of(BvhChannel c) {
  switch (c) {
    case BvhChannel::kXposition:
    case BvhChannel::kXrotation: return Vec3::UnitX();
    case BvhChannel::kYposition:
    case BvhChannel::kYrotation: return Vec3::UnitY();
    case BvhChannel::kZposition:
    case BvhChannel::kZrotation: return Vec3::UnitZ();
  }
  return Vec3::UnitX();
}
bool is_rotation(BvhChannel c) {
  return c == BvhChannel::kXrotation || c == BvhChannel::kYrotation || c == BvhChannel::kZrotation;
}

}  // namespace

std::string_view to_string(BvhChannel channel) {
  return kChannelNames[static_cast<size_t>(channel)];
}

BvhMotion parse_bvh(std::string_view text, std::string_view name) {
  return Parser(text, name).parse();
}

BvhMotion read_bvh(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError::Message(path.string(), "cannot open the BVH file");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return parse_bvh(buffer.str(), path.string());
}

double bvh_fps(double frame_time) {
  const double fps = 1.0 / frame_time;
  const double rounded = std::round(fps);
  return std::abs(fps - rounded) <= 1e-3 * fps ? rounded : fps;
}

core::Quat bvh_local_rotation(const BvhMotion& motion, size_t joint, size_t frame) {
  const BvhJoint& j = motion.joints[joint];
  const std::vector<double>& values = motion.frames[frame];
  Quat q = Quat::Identity();
  for (size_t k = 0; k < j.channels.size(); ++k) {
    if (!is_rotation(j.channels[k])) continue;
    q = q * core::axis_angle(axis_of(j.channels[k]), core::deg_to_rad(values[j.first_channel + k]));
  }
  return q.normalized();
}

std::vector<core::Pose> bvh_forward_kinematics(const BvhMotion& motion, size_t frame) {
  HRIB_CHECK(frame < motion.frames.size()) << "frame " << frame;
  std::vector<core::Pose> X_W(motion.joints.size());
  const std::vector<double>& values = motion.frames[frame];
  for (size_t i = 0; i < motion.joints.size(); ++i) {
    const BvhJoint& j = motion.joints[i];
    core::Pose local;
    local.translation = j.offset;
    for (size_t k = 0; k < j.channels.size(); ++k) {
      if (!is_rotation(j.channels[k])) local.translation += values[j.first_channel + k] * axis_of(j.channels[k]);
    }
    local.rotation = bvh_local_rotation(motion, i, frame);
    X_W[i] = j.parent < 0 ? local : X_W[static_cast<size_t>(j.parent)] * local;
  }
  return X_W;
}

std::string format_bvh(const BvhMotion& motion) {
  std::string out = "HIERARCHY\n";
  // Children lists, to write nested blocks.
  std::vector<std::vector<size_t>> children(motion.joints.size());
  for (size_t i = 0; i < motion.joints.size(); ++i) {
    if (motion.joints[i].parent >= 0) children[static_cast<size_t>(motion.joints[i].parent)].push_back(i);
  }
  const auto vec = [](const Vec3& v) { return fmt::format("{:.6f} {:.6f} {:.6f}", v.x(), v.y(), v.z()); };
  std::function<void(size_t, int)> write = [&](size_t i, int depth) {
    const BvhJoint& j = motion.joints[i];
    const std::string pad(static_cast<size_t>(depth), '\t');
    out += fmt::format("{}{} {}\n{}{{\n", pad, j.parent < 0 ? "ROOT" : "JOINT", j.name, pad);
    out += fmt::format("{}\tOFFSET {}\n{}\tCHANNELS {}", pad, vec(j.offset), pad, j.channels.size());
    for (const BvhChannel c : j.channels) out += fmt::format(" {}", to_string(c));
    out += "\n";
    for (const size_t c : children[i]) write(c, depth + 1);
    if (j.has_end_site) {
      out += fmt::format("{}\tEnd Site\n{}\t{{\n{}\t\tOFFSET {}\n{}\t}}\n", pad, pad, pad,
                         vec(j.end_site), pad);
    }
    out += fmt::format("{}}}\n", pad);
  };
  for (size_t i = 0; i < motion.joints.size(); ++i) {
    if (motion.joints[i].parent < 0) write(i, 0);
  }
  out += fmt::format("MOTION\nFrames: {}\nFrame Time: {:.9f}\n", motion.frames.size(), motion.frame_time);
  for (const auto& frame : motion.frames) {
    for (size_t k = 0; k < frame.size(); ++k) {
      if (k > 0) out += ' ';
      out += fmt::format("{:.6f}", frame[k]);
    }
    out += "\n";
  }
  return out;
}

namespace {

// Euler angles (radians) of R for the channel order, R = R(a1) R(a2) R(a3).
Vec3 euler_angles(const core::Mat3& R, BvhRotationOrder order) {
  if (order == BvhRotationOrder::kZYX) {
    const double b = std::asin(std::clamp(-R(2, 0), -1.0, 1.0));
    return Vec3(std::atan2(R(1, 0), R(0, 0)), b, std::atan2(R(2, 1), R(2, 2)));
  }
  const double b = std::asin(std::clamp(R(0, 2), -1.0, 1.0));
  return Vec3(std::atan2(-R(1, 2), R(2, 2)), b, std::atan2(-R(0, 1), R(0, 0)));
}

// Candidate units (metres per file unit) and the leg length they are judged by.
constexpr std::array<double, 5> kUnits = {1.0, 0.01, 0.0254, 0.056444, 0.001};

}  // namespace

BvhMotion bvh_from_clip(const Clip& clip, BvhRotationOrder order) {
  const core::Mat3 C = y_up_to_z_up().transpose();  // ours -> BVH (y-up)
  constexpr double kCm = 100.0;
  const Skeleton& k = clip.skeleton;
  BvhMotion m;
  m.frame_time = 1.0 / clip.fps;
  // Depth-first order of our joints, children by index.
  std::vector<int> order_of(kNumJoints, -1);
  std::vector<int> dfs;
  std::function<void(int)> visit = [&](int j) {
    order_of[static_cast<size_t>(j)] = static_cast<int>(dfs.size());
    dfs.push_back(j);
    for (int c = j + 1; c < kNumJoints; ++c) {
      if (parent(static_cast<Joint>(c)) == static_cast<Joint>(j)) visit(c);
    }
  };
  visit(0);
  const std::array<BvhChannel, 3> rot =
      order == BvhRotationOrder::kZYX
          ? std::array{BvhChannel::kZrotation, BvhChannel::kYrotation, BvhChannel::kXrotation}
          : std::array{BvhChannel::kXrotation, BvhChannel::kYrotation, BvhChannel::kZrotation};
  for (const int j : dfs) {
    BvhJoint b;
    const auto joint = static_cast<Joint>(j);
    b.name = std::string(joint_name(joint));
    b.parent = j == 0 ? -1 : order_of[static_cast<size_t>(index(*parent(joint)))];
    b.offset = j == 0 ? Vec3::Zero() : Vec3(C * k.offset[static_cast<size_t>(j)] * kCm);
    if (j == 0) b.channels = {BvhChannel::kXposition, BvhChannel::kYposition, BvhChannel::kZposition};
    b.channels.insert(b.channels.end(), rot.begin(), rot.end());
    b.first_channel = m.num_channels;
    m.num_channels += b.channels.size();
    if (joint == Joint::kHead) {
      b.has_end_site = true;
      b.end_site = C * Vec3(0, 0, k.crown_above_neck - k.bone_length(Joint::kHead)) * kCm;
    } else if (joint == Joint::kLeftWrist || joint == Joint::kRightWrist) {
      b.has_end_site = true;
      b.end_site = C * Vec3(0, 0, -k.hand_length) * kCm;
    } else if (joint == Joint::kLeftFoot || joint == Joint::kRightFoot) {
      b.has_end_site = true;
      b.end_site = C * Vec3(0.05 * k.scale, 0, 0) * kCm;
    }
    m.joints.push_back(std::move(b));
  }
  for (const SkeletonPose& pose : clip.frames) {
    std::vector<double> values;
    values.reserve(m.num_channels);
    const Vec3 p = C * pose.X_WP.translation * kCm;
    values.insert(values.end(), {p.x(), p.y(), p.z()});
    for (const int j : dfs) {
      const Quat q = j == 0 ? pose.X_WP.rotation : pose.local[static_cast<size_t>(j)];
      const core::Mat3 R = C * q.toRotationMatrix() * C.transpose();
      const Vec3 a = euler_angles(R, order);
      values.insert(values.end(), {core::rad_to_deg(a.x()), core::rad_to_deg(a.y()), core::rad_to_deg(a.z())});
    }
    m.frames.push_back(std::move(values));
  }
  return m;
}

Clip clip_from_bvh(const BvhMotion& motion, const RetargetOptions& options, std::string_view where) {
  // Joint names, plus "<joint>_end" for End Sites.
  std::vector<std::string> names;
  for (const BvhJoint& j : motion.joints) names.push_back(j.name);
  for (const BvhJoint& j : motion.joints) {
    if (j.has_end_site) names.push_back(j.name + "_end");
  }
  const NameConvention& convention = match_convention(names, where);
  const auto positions = [&](size_t f) {
    const std::vector<core::Pose> X = bvh_forward_kinematics(motion, f);
    std::vector<Vec3> p;
    p.reserve(names.size());
    for (const core::Pose& x : X) p.push_back(x.translation);
    for (size_t i = 0; i < motion.joints.size(); ++i) {
      if (motion.joints[i].has_end_site) p.push_back(X[i] * motion.joints[i].end_site);
    }
    return p;
  };
  // Up axis: the larger of y and z in the pelvis -> head direction of frame 0.
  const JointTargets first = targets_from_named(convention, names, positions(0));
  const Vec3 up = first.joint[index(Joint::kHead)] - first.joint[index(Joint::kPelvis)];
  UpAxis axis = options.up;
  if (axis == UpAxis::kAuto) axis = std::abs(up.y()) >= std::abs(up.z()) ? UpAxis::kY : UpAxis::kZ;
  const core::Mat3 to_ours = axis == UpAxis::kY ? y_up_to_z_up() : core::Mat3::Identity();
  // Unit: the candidate that makes the legs closest to 0.8 m.
  double unit = options.unit_scale.value_or(0);
  if (!options.unit_scale) {
    const double leg = leg_length(first);
    double best = 1e300;
    for (const double u : kUnits) {
      const double err = std::abs(std::log(std::max(leg * u, 1e-12) / 0.8));
      if (err < best) {
        best = err;
        unit = u;
      }
    }
  }
  if (!(unit > 0) || !std::isfinite(unit)) {
    throw core::InputError(std::string(where), "a positive unit scale", fmt::format("{}", unit));
  }
  std::vector<JointTargets> frames;
  frames.reserve(motion.frames.size());
  for (size_t f = 0; f < motion.frames.size(); ++f) {
    std::vector<Vec3> p = positions(f);
    for (Vec3& v : p) v = to_ours * (v * unit);
    frames.push_back(targets_from_named(convention, names, p));
  }
  return clip_from_targets(frames, bvh_fps(motion.frame_time), options, where);
}

}  // namespace hribench::human
