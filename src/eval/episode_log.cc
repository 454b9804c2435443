#include "eval/episode_log.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <fmt/format.h>

#include "core/files.h"
#include "core/rng.h"

namespace hribench::eval {

static_assert(std::endian::native == std::endian::little, "the log format is little-endian");

std::string_view to_string(ContactOther other) {
  switch (other) {
    case ContactOther::kHuman:
      return "human";
    case ContactOther::kEnvironment:
      return "environment";
    case ContactOther::kObject:
      return "object";
  }
  return "unknown";
}

std::string_view to_string(EventKind kind) {
  switch (kind) {
    case EventKind::kActStart:
      return "act_start";
    case EventKind::kActEnd:
      return "act_end";
    case EventKind::kPhase:
      return "phase";
    case EventKind::kCue:
      return "cue";
    case EventKind::kPredicateChange:
      return "predicate_change";
    case EventKind::kContactBegin:
      return "contact_begin";
    case EventKind::kContactEnd:
      return "contact_end";
    case EventKind::kWarning:
      return "warning";
  }
  return "unknown";
}

std::string_view to_string(Actor actor) {
  switch (actor) {
    case Actor::kNone:
      return "none";
    case Actor::kHuman:
      return "human";
    case Actor::kRobot:
      return "robot";
  }
  return "unknown";
}

std::optional<size_t> EpisodeLog::predicate_index(std::string_view name) const {
  for (size_t i = 0; i < predicate_names.size(); ++i) {
    if (predicate_names[i] == name) return i;
  }
  return std::nullopt;
}

std::optional<double> EpisodeLog::event_time(std::string_view name) const {
  for (const Event& e : events) {
    if (e.name == name) return e.time;
  }
  return std::nullopt;
}

double EpisodeLog::duration() const {
  return steps.size() < 2 ? 0.0 : steps.back().time - steps.front().time;
}

namespace {

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

bool same_vec3(const core::Vec3& a, const core::Vec3& b) {
  return same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) && same_bits(a.z(), b.z());
}

bool same_pose(const core::Pose& a, const core::Pose& b) {
  return same_bits(a.rotation.w(), b.rotation.w()) && same_bits(a.rotation.x(), b.rotation.x()) &&
         same_bits(a.rotation.y(), b.rotation.y()) && same_bits(a.rotation.z(), b.rotation.z()) &&
         same_vec3(a.translation, b.translation);
}

template <typename T, typename Same>
bool same_range(const T& a, const T& b, Same same) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), same);
}

bool same_contact(const Contact& a, const Contact& b) {
  return a.robot_part == b.robot_part && a.robot_finger == b.robot_finger &&
         a.other_kind == b.other_kind && a.other == b.other && a.region == b.region &&
         same_bits(a.normal_force, b.normal_force);
}

bool same_quat(const core::Quat& a, const core::Quat& b) {
  return same_bits(a.w(), b.w()) && same_bits(a.x(), b.x()) && same_bits(a.y(), b.y()) &&
         same_bits(a.z(), b.z());
}

bool same_skeleton_pose(const human::SkeletonPose& a, const human::SkeletonPose& b) {
  const auto same_hand = [](const human::HandShape& x, const human::HandShape& y) {
    return same_bits(x.grip, y.grip) && same_bits(x.point, y.point);
  };
  return same_pose(a.X_WP, b.X_WP) && same_range(a.local, b.local, same_quat) &&
         same_range(a.hands, b.hands, same_hand);
}

bool same_step(const StepRecord& a, const StepRecord& b) {
  return same_bits(a.time, b.time) && same_range(a.joint_pos, b.joint_pos, same_bits) &&
         same_range(a.joint_vel, b.joint_vel, same_bits) && same_pose(a.X_WT, b.X_WT) &&
         same_bits(a.gripper_width, b.gripper_width) &&
         same_range(a.finger_pos, b.finger_pos, same_bits) &&
         same_range(a.action, b.action, same_bits) &&
         same_range(a.joint_target, b.joint_target, same_bits) &&
         same_bits(a.gripper_target, b.gripper_target) &&
         same_range(a.human_joints_W, b.human_joints_W, same_vec3) &&
         same_skeleton_pose(a.human_pose, b.human_pose) &&
         same_range(a.object_poses, b.object_poses, same_pose) &&
         same_range(a.lid_angles, b.lid_angles, same_bits) &&
         same_bits(a.separation, b.separation) && same_bits(a.approach_speed, b.approach_speed) &&
         same_bits(a.closest_point_speed, b.closest_point_speed) &&
         same_range(a.contacts, b.contacts, same_contact) && a.predicates == b.predicates;
}

bool same_event(const Event& a, const Event& b) {
  return same_bits(a.time, b.time) && a.kind == b.kind && a.actor == b.actor &&
         a.name == b.name && a.detail == b.detail;
}

}  // namespace

bool identical(const EpisodeLog& a, const EpisodeLog& b) {
  return a.task == b.task && a.role == b.role && a.spec_hash == b.spec_hash && a.seed == b.seed &&
         a.policy == b.policy && a.robot == b.robot && same_bits(a.horizon, b.horizon) &&
         same_bits(a.control_dt, b.control_dt) && a.action_space == b.action_space &&
         a.object_names == b.object_names &&
         a.predicate_names == b.predicate_names && same_range(a.steps, b.steps, same_step) &&
         same_range(a.events, b.events, same_event) && a.status == b.status &&
         a.status_reason == b.status_reason;
}

void check_episode_log(const EpisodeLog& log, std::string_view where) {
  const std::string w(where);
  for (size_t k = 0; k < log.steps.size(); ++k) {
    const StepRecord& s = log.steps[k];
    const std::string at = fmt::format("{}: step {}", w, k);
    if (!std::isfinite(s.time) || (k > 0 && !(s.time > log.steps[k - 1].time))) {
      throw core::InputError(at, "a finite time after the previous step's",
                             fmt::format("{}", s.time));
    }
    if (s.object_poses.size() != log.object_names.size()) {
      throw core::InputError(at, fmt::format("{} object poses", log.object_names.size()),
                             fmt::format("{}", s.object_poses.size()));
    }
    if (s.lid_angles.size() != log.object_names.size()) {
      throw core::InputError(at, fmt::format("{} lid angles", log.object_names.size()),
                             fmt::format("{}", s.lid_angles.size()));
    }
    const size_t dim = static_cast<size_t>(policy::action_dim(log.action_space, s.joint_pos.size()));
    if (!s.action.empty() && s.action.size() != dim) {
      throw core::InputError(at, fmt::format("no action or {} values ({})", dim,
                                             policy::to_string(log.action_space)),
                             fmt::format("{} values", s.action.size()));
    }
    if (s.predicates.size() != log.predicate_names.size()) {
      throw core::InputError(at, fmt::format("{} predicate values", log.predicate_names.size()),
                             fmt::format("{}", s.predicates.size()));
    }
    for (const Contact& c : s.contacts) {
      if (!(c.normal_force >= 0)) {
        throw core::InputError(at + " contact " + c.robot_part + "|" + c.other,
                               "a normal force >= 0", fmt::format("{}", c.normal_force));
      }
      if ((c.other_kind == ContactOther::kHuman) != c.region.has_value()) {
        throw core::InputError(at + " contact " + c.robot_part + "|" + c.other,
                               "a body region exactly for human contacts",
                               c.region ? "a region on a non-human contact" : "no region");
      }
    }
  }
  for (size_t i = 1; i < log.events.size(); ++i) {
    if (log.events[i].time < log.events[i - 1].time) {
      throw core::InputError(fmt::format("{}: event {} ({})", w, i, log.events[i].name),
                             "events in time order", fmt::format("{}", log.events[i].time));
    }
  }
}

namespace {

constexpr char kMagic[8] = {'H', 'R', 'I', 'B', 'L', 'O', 'G', '\0'};

// Appends plain little-endian values to a byte string.
class Writer {
 public:
  template <typename T>
  void put(T value) {
    static_assert(std::is_trivially_copyable_v<T>);
    char bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    out_.append(bytes, sizeof(T));
  }
  void put_string(std::string_view s) {
    put<uint64_t>(s.size());
    out_.append(s);
  }
  void put_vec3(const core::Vec3& v) {
    for (int i = 0; i < 3; ++i) put<double>(v[i]);
  }
  void put_quat(const core::Quat& q) {
    put<double>(q.w());
    put<double>(q.x());
    put<double>(q.y());
    put<double>(q.z());
  }
  void put_pose(const core::Pose& p) {
    put_quat(p.rotation);
    put_vec3(p.translation);
  }
  void put_doubles(const std::vector<double>& values) {
    put<uint64_t>(values.size());
    for (const double v : values) put<double>(v);
  }
  std::string& bytes() { return out_; }

 private:
  std::string out_;
};

// Reads what Writer wrote; every read past the end is a truncation error.
class Reader {
 public:
  Reader(std::string_view bytes, std::string where) : in_(bytes), where_(std::move(where)) {}
  template <typename T>
  T get(const char* what) {
    need(sizeof(T), what);
    T value;
    std::memcpy(&value, in_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return value;
  }
  std::string get_string(const char* what) {
    const uint64_t n = get<uint64_t>(what);
    need(n, what);
    std::string s(in_.substr(pos_, n));
    pos_ += n;
    return s;
  }
  // A count of items, each at least `min_item_bytes` (> 0) long: a count the bytes left cannot
  // hold is corrupt (so a short file never asks for a huge allocation).
  size_t get_count(const char* what, size_t min_item_bytes) {
    const uint64_t n = get<uint64_t>(what);
    if (n > (in_.size() - pos_) / min_item_bytes) corrupt(what);
    return static_cast<size_t>(n);
  }
  std::vector<double> get_doubles(const char* what) {
    std::vector<double> values(get_count(what, sizeof(double)));
    for (double& v : values) v = get<double>(what);
    return values;
  }
  core::Quat get_quat(const char* what) {
    const double w = get<double>(what);
    const double x = get<double>(what);
    const double y = get<double>(what);
    const double z = get<double>(what);
    return core::Quat(w, x, y, z);
  }
  core::Vec3 get_vec3(const char* what) {
    core::Vec3 v;
    for (int i = 0; i < 3; ++i) v[i] = get<double>(what);
    return v;
  }
  core::Pose get_pose(const char* what) {
    core::Pose p;
    p.rotation = get_quat(what);
    p.translation = get_vec3(what);
    return p;
  }
  template <typename E>
  E get_enum(const char* what, int count) {
    const uint8_t v = get<uint8_t>(what);
    if (v >= count) corrupt(what);
    return static_cast<E>(v);
  }
  bool at_end() const { return pos_ == in_.size(); }
  [[noreturn]] void corrupt(const char* what) const {
    throw core::InputError::Message(where_,
                                    fmt::format("corrupt episode log (bad {} at byte {})", what, pos_));
  }

 private:
  void need(uint64_t n, const char* what) const {
    if (n > in_.size() - pos_) {
      throw core::InputError::Message(
          where_, fmt::format("truncated episode log (ends inside {} at byte {})", what, pos_));
    }
  }
  std::string_view in_;
  size_t pos_ = 0;
  std::string where_;
};

// The fewest bytes each item can take in the payload (empty strings and lists), against which
// every declared count is checked.
constexpr size_t kStringBytes = sizeof(uint64_t);
constexpr size_t kPoseBytes = 7 * sizeof(double);
constexpr size_t kContactBytes = 2 * kStringBytes + 3 * sizeof(uint8_t) + sizeof(double);
constexpr size_t kEventBytes = sizeof(double) + 2 * sizeof(uint8_t) + 2 * kStringBytes;
size_t min_step_bytes(const EpisodeLog& log) {
  const size_t objects = log.object_names.size();
  return sizeof(double)                                  // time
         + 2 * sizeof(uint64_t)                          // joint positions, velocities
         + kPoseBytes + sizeof(double) + 2 * sizeof(double)  // X_WT, gripper, fingers
         + 2 * sizeof(uint64_t) + sizeof(double)         // action, joint targets, gripper target
         + human::kNumJoints * 3 * sizeof(double)        // human joint positions
         + kPoseBytes + human::kNumJoints * 4 * sizeof(double)  // human skeleton pose
         + 2 * 2 * sizeof(double)                        // hand shapes
         + objects * (kPoseBytes + sizeof(double))       // object poses, lid angles
         + 3 * sizeof(double) + sizeof(uint64_t)         // separation, speeds, contact count
         + log.predicate_names.size();                   // predicate values
}

void write_payload(const EpisodeLog& log, Writer& w) {
  w.put_string(log.task);
  w.put_string(log.role);
  w.put_string(log.spec_hash);
  w.put<uint64_t>(log.seed);
  w.put_string(log.policy);
  w.put_string(log.robot);
  w.put<double>(log.horizon);
  w.put<double>(log.control_dt);
  w.put<uint8_t>(static_cast<uint8_t>(log.action_space));
  w.put<uint64_t>(log.object_names.size());
  for (const std::string& n : log.object_names) w.put_string(n);
  w.put<uint64_t>(log.predicate_names.size());
  for (const std::string& n : log.predicate_names) w.put_string(n);
  w.put<uint8_t>(static_cast<uint8_t>(log.status));
  w.put_string(log.status_reason);
  w.put<uint64_t>(log.steps.size());
  for (const StepRecord& s : log.steps) {
    w.put<double>(s.time);
    w.put_doubles(s.joint_pos);
    w.put_doubles(s.joint_vel);
    w.put_pose(s.X_WT);
    w.put<double>(s.gripper_width);
    for (const double f : s.finger_pos) w.put<double>(f);
    w.put_doubles(s.action);
    w.put_doubles(s.joint_target);
    w.put<double>(s.gripper_target);
    for (const core::Vec3& p : s.human_joints_W) w.put_vec3(p);
    w.put_pose(s.human_pose.X_WP);
    for (const core::Quat& q : s.human_pose.local) w.put_quat(q);
    for (const human::HandShape& h : s.human_pose.hands) {
      w.put<double>(h.grip);
      w.put<double>(h.point);
    }
    for (const core::Pose& p : s.object_poses) w.put_pose(p);
    for (const double a : s.lid_angles) w.put<double>(a);
    w.put<double>(s.separation);
    w.put<double>(s.approach_speed);
    w.put<double>(s.closest_point_speed);
    w.put<uint64_t>(s.contacts.size());
    for (const Contact& c : s.contacts) {
      w.put_string(c.robot_part);
      w.put<uint8_t>(c.robot_finger ? 1 : 0);
      w.put<uint8_t>(static_cast<uint8_t>(c.other_kind));
      w.put_string(c.other);
      w.put<uint8_t>(c.region ? static_cast<uint8_t>(*c.region) : uint8_t{255});
      w.put<double>(c.normal_force);
    }
    for (const uint8_t b : s.predicates) w.put<uint8_t>(b);
  }
  w.put<uint64_t>(log.events.size());
  for (const Event& e : log.events) {
    w.put<double>(e.time);
    w.put<uint8_t>(static_cast<uint8_t>(e.kind));
    w.put<uint8_t>(static_cast<uint8_t>(e.actor));
    w.put_string(e.name);
    w.put_string(e.detail);
  }
}

EpisodeLog read_payload(Reader& r) {
  EpisodeLog log;
  log.task = r.get_string("task");
  log.role = r.get_string("role");
  log.spec_hash = r.get_string("spec_hash");
  log.seed = r.get<uint64_t>("seed");
  log.policy = r.get_string("policy");
  log.robot = r.get_string("robot");
  log.horizon = r.get<double>("horizon");
  log.control_dt = r.get<double>("control_dt");
  log.action_space = r.get_enum<policy::ActionSpace>("action space", 2);
  log.object_names.resize(r.get_count("object count", kStringBytes));
  for (std::string& n : log.object_names) n = r.get_string("object name");
  log.predicate_names.resize(r.get_count("predicate count", kStringBytes));
  for (std::string& n : log.predicate_names) n = r.get_string("predicate name");
  log.status = r.get_enum<core::EpisodeStatus>("status", 3);
  log.status_reason = r.get_string("status reason");
  log.steps.resize(r.get_count("step count", min_step_bytes(log)));
  for (StepRecord& s : log.steps) {
    s.time = r.get<double>("step time");
    s.joint_pos = r.get_doubles("joint positions");
    s.joint_vel = r.get_doubles("joint velocities");
    s.X_WT = r.get_pose("end-effector pose");
    s.gripper_width = r.get<double>("gripper width");
    for (double& f : s.finger_pos) f = r.get<double>("finger position");
    s.action = r.get_doubles("action");
    s.joint_target = r.get_doubles("joint targets");
    s.gripper_target = r.get<double>("gripper target");
    for (core::Vec3& p : s.human_joints_W) p = r.get_vec3("human joint");
    s.human_pose.X_WP = r.get_pose("human root pose");
    for (core::Quat& q : s.human_pose.local) q = r.get_quat("human joint rotation");
    for (human::HandShape& h : s.human_pose.hands) {
      h.grip = r.get<double>("hand grip");
      h.point = r.get<double>("hand point");
    }
    s.object_poses.resize(log.object_names.size());
    for (core::Pose& p : s.object_poses) p = r.get_pose("object pose");
    s.lid_angles.resize(log.object_names.size());
    for (double& a : s.lid_angles) a = r.get<double>("lid angle");
    s.separation = r.get<double>("separation");
    s.approach_speed = r.get<double>("approach speed");
    s.closest_point_speed = r.get<double>("closest-point speed");
    s.contacts.resize(r.get_count("contact count", kContactBytes));
    for (Contact& c : s.contacts) {
      c.robot_part = r.get_string("contact robot part");
      c.robot_finger = r.get<uint8_t>("contact finger flag") != 0;
      c.other_kind = r.get_enum<ContactOther>("contact kind", 3);
      c.other = r.get_string("contact other");
      const uint8_t region = r.get<uint8_t>("contact region");
      if (region != 255) {
        if (region >= human::kNumBodyRegions) r.corrupt("contact region");
        c.region = static_cast<human::BodyRegion>(region);
      }
      c.normal_force = r.get<double>("contact force");
    }
    s.predicates.resize(log.predicate_names.size());
    for (uint8_t& b : s.predicates) {
      b = r.get<uint8_t>("predicate value");
      if (b > 1) r.corrupt("predicate value");
    }
  }
  log.events.resize(r.get_count("event count", kEventBytes));
  for (Event& e : log.events) {
    e.time = r.get<double>("event time");
    e.kind = r.get_enum<EventKind>("event kind", 8);
    e.actor = r.get_enum<Actor>("event actor", 3);
    e.name = r.get_string("event name");
    e.detail = r.get_string("event detail");
  }
  return log;
}

}  // namespace

std::string encode_episode_log(const EpisodeLog& log) {
  Writer payload;
  write_payload(log, payload);
  Writer file;
  file.bytes().append(kMagic, sizeof(kMagic));
  file.put<uint32_t>(kEpisodeLogVersion);
  file.put<uint64_t>(payload.bytes().size());
  file.bytes().append(payload.bytes());
  file.put<uint64_t>(core::fnv1a64(payload.bytes()));
  return std::move(file.bytes());
}

EpisodeLog decode_episode_log(std::string_view bytes, std::string_view where) {
  const std::string w(where);
  Reader header(bytes, w);
  if (bytes.size() < sizeof(kMagic) || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    throw core::InputError(w, "an HRIBench episode log (starting with HRIBLOG)",
                           "a file of another kind");
  }
  for (size_t i = 0; i < sizeof(kMagic); ++i) header.get<char>("magic");
  const uint32_t version = header.get<uint32_t>("format version");
  if (version != kEpisodeLogVersion) {
    throw core::InputError(w, fmt::format("episode log format version {}", kEpisodeLogVersion),
                           fmt::format("format version {}", version));
  }
  const uint64_t size = header.get<uint64_t>("payload size");
  const size_t head = sizeof(kMagic) + sizeof(uint32_t) + sizeof(uint64_t);
  if (bytes.size() - head < size || bytes.size() - head - size < sizeof(uint64_t)) {
    throw core::InputError::Message(
        w, fmt::format("truncated episode log ({} bytes, expected {})", bytes.size(),
                       head + size + sizeof(uint64_t)));
  }
  if (bytes.size() - head - size > sizeof(uint64_t)) {
    throw core::InputError::Message(w, "corrupt episode log (trailing bytes after the checksum)");
  }
  const std::string_view payload = bytes.substr(head, size);
  uint64_t checksum = 0;
  std::memcpy(&checksum, bytes.data() + head + size, sizeof(checksum));
  if (checksum != core::fnv1a64(payload)) {
    throw core::InputError::Message(w, "corrupt episode log (checksum mismatch)");
  }
  Reader reader(payload, w);
  EpisodeLog log = read_payload(reader);
  if (!reader.at_end()) reader.corrupt("payload length");
  check_episode_log(log, w);
  return log;
}

void save_episode_log(const EpisodeLog& log, const std::filesystem::path& path) {
  core::write_file_atomically(path, encode_episode_log(log));
}

EpisodeLog load_episode_log(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw core::InputError::Message(path.string(), "cannot open the episode log");
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  return decode_episode_log(bytes, path.string());
}

}  // namespace hribench::eval
