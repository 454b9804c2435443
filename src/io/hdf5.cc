#include "io/hdf5.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <functional>
#include <mutex>
#include <utility>

#include <fmt/format.h>
#include <hdf5.h>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include "core/errors.h"
#include "core/files.h"
#include "core/json.h"
#include "core/version.h"

namespace hribench::io {

namespace fs = std::filesystem;

namespace {

// Debian's libhdf5 is built without thread safety: one lock for every call.
std::mutex& hdf5_mutex() {
  static std::mutex mutex;
  return mutex;
}
using Hdf5Lock = std::lock_guard<std::mutex>;

// Silences HDF5's own error printing (errors become exceptions here); under the lock.
void quiet() {
  static const bool once = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)once;
}

// An HDF5 id closed by `close` when it goes out of scope (always under the lock).
class Id {
 public:
  Id() = default;
  Id(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Id(Id&& other) noexcept : id_(std::exchange(other.id_, -1)), close_(other.close_) {}
  Id& operator=(Id&& other) noexcept {
    reset();
    id_ = std::exchange(other.id_, -1);
    close_ = other.close_;
    return *this;
  }
  ~Id() { reset(); }
  void reset() {
    if (id_ >= 0 && close_ != nullptr) close_(id_);
    id_ = -1;
  }
  hid_t get() const { return id_; }
  operator hid_t() const { return id_; }

 private:
  hid_t id_ = -1;
  herr_t (*close_)(hid_t) = nullptr;
};

// Throws "FILE: cannot write (WHAT)" when an HDF5 call failed.
hid_t check_id(hid_t id, const fs::path& file, std::string_view what) {
  if (id < 0) throw core::InputError::Message(file.string(), "HDF5 cannot " + std::string(what));
  return id;
}
void check(herr_t status, const fs::path& file, std::string_view what) {
  if (status < 0) throw core::InputError::Message(file.string(), "HDF5 cannot " + std::string(what));
}

Id create_file(const fs::path& path) {
  quiet();
  return {check_id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), path, "create the file"), H5Fclose};
}
Id open_file(const fs::path& path, bool write) {
  quiet();
  return {check_id(H5Fopen(path.c_str(), write ? H5F_ACC_RDWR : H5F_ACC_RDONLY, H5P_DEFAULT), path, "open the file"),
          H5Fclose};
}
// Objects carry no creation times, so the same episode gives the same bytes.
Id create_group(hid_t at, const std::string& name, const fs::path& file) {
  const Id properties(H5Pcreate(H5P_GROUP_CREATE), H5Pclose);
  H5Pset_obj_track_times(properties, false);
  return {check_id(H5Gcreate2(at, name.c_str(), H5P_DEFAULT, properties, H5P_DEFAULT), file, "create group " + name),
          H5Gclose};
}

// A dataset of `type` and `dims`; chunked by `chunk` (empty: contiguous); deflate-filtered
// when `deflate`; extensible along the first axis when `extensible`.
Id create_dataset(hid_t at, const std::string& name, hid_t type, const std::vector<hsize_t>& dims,
                  const std::vector<hsize_t>& chunk, bool deflate, bool extensible, const fs::path& file) {
  std::vector<hsize_t> max = dims;
  if (extensible) max[0] = H5S_UNLIMITED;
  const Id space(check_id(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), max.data()), file, "make a dataspace"),
                 H5Sclose);
  const Id properties(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_obj_track_times(properties, false);
  if (!chunk.empty()) check(H5Pset_chunk(properties, static_cast<int>(chunk.size()), chunk.data()), file, "chunk " + name);
  if (deflate) check(H5Pset_deflate(properties, 4), file, "compress " + name);
  return {check_id(H5Dcreate2(at, name.c_str(), type, space, H5P_DEFAULT, properties, H5P_DEFAULT), file,
                   "create dataset " + name),
          H5Dclose};
}

// A whole dataset of `type` and `dims` from row-major `data`.
template <typename T>
void write_array(hid_t at, const std::string& name, hid_t type, const std::vector<T>& data,
                 const std::vector<hsize_t>& dims, const fs::path& file) {
  const Id d = create_dataset(at, name, type, dims, {}, false, false, file);
  if (!data.empty()) check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()), file, "write " + name);
}
// (rows, columns) from row-major `data`.
template <typename T>
void write_matrix(hid_t at, const std::string& name, hid_t type, const std::vector<T>& data, hsize_t rows,
                  const fs::path& file) {
  write_array(at, name, type, data, {rows, rows > 0 ? data.size() / rows : 0}, file);
}
// (n,).
template <typename T>
void write_vector(hid_t at, const std::string& name, hid_t type, const std::vector<T>& data, const fs::path& file) {
  write_array(at, name, type, data, {data.size()}, file);
}

Id string_type() {
  Id type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, H5T_VARIABLE);
  H5Tset_cset(type, H5T_CSET_UTF8);
  return type;
}

void write_strings(hid_t at, const std::string& name, const std::vector<std::string>& values, const fs::path& file) {
  const Id type = string_type();
  std::vector<const char*> pointers;
  for (const std::string& v : values) pointers.push_back(v.c_str());
  const Id d = create_dataset(at, name, type, {values.size()}, {}, false, false, file);
  if (!values.empty()) check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, pointers.data()), file, "write " + name);
}

void write_attribute(hid_t at, const std::string& name, hid_t type, const void* value, const fs::path& file) {
  const Id space(H5Screate(H5S_SCALAR), H5Sclose);
  if (H5Aexists(at, name.c_str()) > 0) H5Adelete(at, name.c_str());
  const Id a(check_id(H5Acreate2(at, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), file, "create attribute " + name),
             H5Aclose);
  check(H5Awrite(a, type, value), file, "write attribute " + name);
}
void write_attribute(hid_t at, const std::string& name, const std::string& value, const fs::path& file) {
  const Id type = string_type();
  const char* pointer = value.c_str();
  write_attribute(at, name, type, &pointer, file);
}
void write_attribute(hid_t at, const std::string& name, int64_t value, const fs::path& file) {
  write_attribute(at, name, H5T_NATIVE_INT64, &value, file);
}
void write_attribute_u64(hid_t at, const std::string& name, uint64_t value, const fs::path& file) {
  write_attribute(at, name, H5T_NATIVE_UINT64, &value, file);
}
// A bool as h5py stores one (an int8 enum FALSE = 0, TRUE = 1), read back as numpy.bool_.
void write_attribute_bool(hid_t at, const std::string& name, bool value, const fs::path& file) {
  const Id type(H5Tenum_create(H5T_NATIVE_INT8), H5Tclose);
  const int8_t no = 0;
  const int8_t yes = 1;
  H5Tenum_insert(type, "FALSE", &no);
  H5Tenum_insert(type, "TRUE", &yes);
  const int8_t v = value ? 1 : 0;
  write_attribute(at, name, type, &v, file);
}

std::string read_string_attribute(hid_t at, const std::string& name, const fs::path& file) {
  const Id a(check_id(H5Aopen(at, name.c_str(), H5P_DEFAULT), file, "find attribute " + name), H5Aclose);
  const Id type = string_type();
  char* value = nullptr;
  check(H5Aread(a, type, &value), file, "read attribute " + name);
  std::string out = value != nullptr ? value : "";
  H5free_memory(value);
  return out;
}
template <typename T>
T read_attribute(hid_t at, const std::string& name, hid_t type, const fs::path& file) {
  const Id a(check_id(H5Aopen(at, name.c_str(), H5P_DEFAULT), file, "find attribute " + name), H5Aclose);
  T value{};
  check(H5Aread(a, type, &value), file, "read attribute " + name);
  return value;
}

// Rows [0, rows) of a (N, columns) float32 dataset.
std::vector<std::vector<float>> read_rows(hid_t at, const std::string& name, hsize_t rows, const fs::path& file) {
  const Id d(check_id(H5Dopen2(at, name.c_str(), H5P_DEFAULT), file, "find dataset " + name), H5Dclose);
  const Id space(H5Dget_space(d), H5Sclose);
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_ndims(space) != 2) throw core::InputError(file.string() + " " + name, "a 2-D dataset", "another");
  H5Sget_simple_extent_dims(space, dims, nullptr);
  if (dims[0] < rows) {
    throw core::InputError(file.string() + " " + name, fmt::format("at least {} rows", rows), std::to_string(dims[0]));
  }
  std::vector<float> all(dims[0] * dims[1]);
  if (!all.empty()) check(H5Dread(d, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data()), file, "read " + name);
  std::vector<std::vector<float>> out;
  for (hsize_t r = 0; r < rows; ++r) out.emplace_back(all.begin() + static_cast<long>(r * dims[1]), all.begin() + static_cast<long>((r + 1) * dims[1]));
  return out;
}

// An image compressed as HDF5's deflate filter stores a chunk (a zlib stream); outside the lock.
std::vector<uint8_t> deflate_image(const render::Image& image, const fs::path& file) {
  uLongf size = compressBound(static_cast<uLong>(image.rgb.size()));
  std::vector<uint8_t> out(size);
  if (compress2(out.data(), &size, image.rgb.data(), static_cast<uLong>(image.rgb.size()), 4) != Z_OK) {
    throw core::InputError::Message(file.string(), "cannot compress an image");
  }
  out.resize(size);
  return out;
}

void write_chunk(hid_t dataset, hsize_t row, const std::vector<uint8_t>& chunk, const fs::path& file) {
  const hsize_t offset[4] = {row, 0, 0, 0};
  check(H5Dwrite_chunk(dataset, H5P_DEFAULT, 0, offset, chunk.size(), chunk.data()), file, "write an image");
}

// The dimensions of the state group `group` (names GROUP.PART), in order.
std::vector<size_t> group_dims(const std::vector<std::string>& names, const std::string& group) {
  std::vector<size_t> dims;
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i].substr(0, names[i].find('.')) == group) dims.push_back(i);
  }
  return dims;
}
std::vector<size_t> named_dims(const std::vector<std::string>& names, const std::vector<std::string>& wanted,
                               const std::string& where) {
  std::vector<size_t> dims;
  for (const std::string& w : wanted) {
    const auto at = std::find(names.begin(), names.end(), w);
    if (at == names.end()) throw core::InputError(where, "a state with " + w, "a state without it");
    dims.push_back(static_cast<size_t>(at - names.begin()));
  }
  return dims;
}
// The groups of GROUP.PART names, in order of first appearance.
std::vector<std::string> groups_of(const std::vector<std::string>& names) {
  std::vector<std::string> groups;
  for (const std::string& n : names) {
    const std::string g = n.substr(0, n.find('.'));
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
  }
  return groups;
}

std::string json_list(const std::vector<std::string>& values) { return nlohmann::json(values).dump(); }

// The episode's identity as root / demo attributes.
void write_identity(hid_t at, const EpisodeHeader& h, int64_t frames, const fs::path& file) {
  write_attribute(at, "task", h.task, file);
  write_attribute(at, "task_id", h.task_id, file);
  write_attribute(at, "role", h.role, file);
  write_attribute(at, "instruction", h.instruction, file);
  write_attribute(at, "spec_hash", h.spec_hash, file);
  write_attribute_u64(at, "seed", h.seed, file);
  write_attribute(at, "variant", h.variant, file);
  write_attribute(at, "policy", h.policy, file);
  write_attribute(at, "robot", h.robot, file);
  write_attribute(at, "fps", int64_t{h.fps}, file);
  write_attribute(at, "action_space", h.action_space, file);
  write_attribute(at, "state_names", json_list(h.state_names), file);
  write_attribute(at, "action_names", json_list(h.action_names), file);
  write_attribute(at, "frames", frames, file);
  write_attribute(at, "hribench_version", std::string(core::version()), file);
}
void write_outcome(hid_t at, const EpisodeOutcome& o, const fs::path& file) {
  write_attribute_bool(at, "success", o.success, file);
  write_attribute(at, "status", std::string(core::to_string(o.status)), file);
  write_attribute(at, "failure_labels", json_list(o.failure_labels), file);
}

std::atomic<uint64_t> temporary_counter{0};
fs::path temporary_path(const fs::path& folder, const std::string& stem) {
  return folder / fmt::format(".{}.{}.hdf5.tmp", stem, temporary_counter++);
}

// The frames but their images, row after row.
struct LowDim {
  std::vector<float> state;   // rows of header.state_names
  std::vector<float> action;  // rows of header.action_names
  std::vector<std::string> human_act;
  std::vector<std::string> events;
  std::vector<float> reward;
  std::vector<double> sim_state;
  std::vector<uint8_t> done;
  int64_t frames = 0;
  void add(const Frame& f) {
    state.insert(state.end(), f.state.begin(), f.state.end());
    action.insert(action.end(), f.action.begin(), f.action.end());
    human_act.push_back(f.human_act);
    std::string joined;
    for (const std::string& e : f.events) joined += (joined.empty() ? "" : ";") + e;
    events.push_back(joined);
    reward.push_back(f.reward);
    sim_state.insert(sim_state.end(), f.sim_state.begin(), f.sim_state.end());
    done.push_back(f.done ? 1 : 0);
    ++frames;
  }
};

void check_frame(const EpisodeHeader& h, const Frame& f, const fs::path& file) {
  if (f.state.size() != h.state_names.size() || f.action.size() != h.action_names.size() ||
      f.images.size() != h.cameras.size()) {
    throw core::InputError(file.string() + " frame " + std::to_string(f.index),
                           fmt::format("{} state, {} action values and {} images", h.state_names.size(),
                                       h.action_names.size(), h.cameras.size()),
                           fmt::format("{}, {} and {}", f.state.size(), f.action.size(), f.images.size()));
  }
  for (size_t c = 0; c < h.cameras.size(); ++c) {
    if (f.images[c]->width != h.cameras[c].width || f.images[c]->height != h.cameras[c].height) {
      throw core::InputError(file.string() + " camera " + h.cameras[c].name,
                             fmt::format("{}x{} images", h.cameras[c].width, h.cameras[c].height),
                             fmt::format("{}x{}", f.images[c]->width, f.images[c]->height));
    }
  }
}

// ---------------------------------------------------------------------------------------------
// ACT

// An episode written to its own file at a temporary name: images streamed (datasets_), the rest
// written when the last frame arrives (seal), the outcome added and the file renamed by commit;
// removed unless committed.
class FileSink : public EpisodeSink {
 public:
  FileSink(EpisodeHeader header, fs::path path) : header_(std::move(header)), path_(std::move(path)) {}
  ~FileSink() override {
    const Hdf5Lock lock(hdf5_mutex());
    images_.clear();
    file_.reset();
    std::error_code ec;
    if (!committed_) fs::remove(path_, ec);
  }
  const EpisodeHeader& header() const { return header_; }
  // Moves the complete file to FOLDER/episode.hdf5, the header to FOLDER/episode.json
  // (DatasetWriter::store; `format` names the writer).
  void store(const fs::path& folder, const char* format) {
    if (!closed_) throw core::InputError(path_.string(), "a complete episode (its last frame)", "an episode cut short");
    fs::create_directories(folder);
    fs::rename(path_, folder / "episode.hdf5");
    committed_ = true;  // moved away: nothing to remove
    const nlohmann::json stored = {{"format", format}, {"header", episode_header_json(header_)}};
    core::write_file_atomically(folder / "episode.json", stored.dump() + "\n");
  }
  // Adds the outcome to `group` ("/" or a group's name) and renames the file to `path`.
  void commit(const EpisodeOutcome& outcome, const fs::path& path, const char* group) {
    if (!closed_) throw core::InputError(path.string(), "a complete episode (its last frame)", "an episode cut short");
    {
      const Hdf5Lock lock(hdf5_mutex());
      const Id file = open_file(path_, true);
      const Id at(check_id(H5Gopen2(file, group, H5P_DEFAULT), path_, "open group"), H5Gclose);
      write_outcome(at, outcome, path_);
    }
    fs::rename(path_, path);
    committed_ = true;
  }

 protected:
  // Closes the complete file (under the lock).
  void seal() {
    images_.clear();
    check(H5Fflush(file_, H5F_SCOPE_GLOBAL), path_, "flush the file");
    file_.reset();
    closed_ = true;
  }
  EpisodeHeader header_;
  fs::path path_;
  Id file_;
  std::vector<Id> images_;
  LowDim rows_;
  bool closed_ = false;
  bool committed_ = false;
};

// A complete episode stored by FileSink::store, copied to `path` to be committed
// (DatasetWriter::load): it takes no frames.
class StoredSink : public FileSink {
 public:
  StoredSink(EpisodeHeader header, fs::path path) : FileSink(std::move(header), std::move(path)) { closed_ = true; }
  void add(const Frame&) override {
    throw core::InputError(path_.string(), "no frames (a stored episode is complete)", "a frame");
  }
};

// The episode FOLDER/episode.hdf5 a writer of `format` stored, copied to a temporary name in
// the folder `into(header)` names.
std::unique_ptr<FileSink> load_stored(const fs::path& folder, const char* format,
                                      const std::function<fs::path(const EpisodeHeader&)>& into, const char* stem) {
  const std::string where = (folder / "episode.json").string();
  const nlohmann::json stored = core::read_json_file(where);
  if (!stored.is_object() || stored.value("format", nlohmann::json()) != format) {
    throw core::InputError(where, std::string("an episode stored by the ") + format + " writer", "other JSON");
  }
  EpisodeHeader header = episode_header_from_json(core::json_member(stored, "header", where), where + ": header");
  const fs::path target = into(header);
  fs::create_directories(target);
  const fs::path path = temporary_path(target, stem);
  std::error_code error;
  fs::copy_file(folder / "episode.hdf5", path, error);
  if (error) throw core::InputError::Message((folder / "episode.hdf5").string(), "cannot be copied: " + error.message());
  return std::make_unique<StoredSink>(std::move(header), path);
}

class ActSink : public FileSink {
 public:
  ActSink(const fs::path& folder, EpisodeHeader header)
      : FileSink(std::move(header), temporary_path(folder, "episode")) {
    const hsize_t T = static_cast<hsize_t>(header_.max_frames);
    const Hdf5Lock lock(hdf5_mutex());
    file_ = create_file(path_);
    const Id observations = create_group(file_, "observations", path_);
    const Id images = create_group(observations, "images", path_);
    for (const CameraSpec& c : header_.cameras) {
      const hsize_t H = static_cast<hsize_t>(c.height), W = static_cast<hsize_t>(c.width);
      images_.push_back(create_dataset(images, c.name, H5T_NATIVE_UINT8, {T, H, W, 3}, {1, H, W, 3}, true, false, path_));
    }
    last_chunks_.resize(header_.cameras.size());
  }

  void add(const Frame& f) override {
    check_frame(header_, f, path_);
    if (f.index >= header_.max_frames) {
      throw core::InputError(path_.string(), fmt::format("at most {} frames (the task's horizon)", header_.max_frames),
                             "frame " + std::to_string(f.index));
    }
    for (size_t c = 0; c < f.images.size(); ++c) last_chunks_[c] = deflate_image(*f.images[c], path_);
    {
      const Hdf5Lock lock(hdf5_mutex());
      for (size_t c = 0; c < f.images.size(); ++c) write_chunk(images_[c], static_cast<hsize_t>(f.index), last_chunks_[c], path_);
    }
    rows_.add(f);
    if (f.done) close();
  }

  // Pads to the task's length with the final frame and writes everything but the images.
  void close() {
    const int64_t frames = rows_.frames;
    const int64_t T = header_.max_frames;
    const size_t S = header_.state_names.size(), A = header_.action_names.size();
    const std::vector<float> last_state(rows_.state.end() - static_cast<long>(S), rows_.state.end());
    const std::vector<float> last_action(rows_.action.end() - static_cast<long>(A), rows_.action.end());
    for (int64_t k = frames; k < T; ++k) {
      rows_.state.insert(rows_.state.end(), last_state.begin(), last_state.end());
      rows_.action.insert(rows_.action.end(), last_action.begin(), last_action.end());
      rows_.human_act.push_back(rows_.human_act.back());
      rows_.events.push_back("");
      rows_.reward.push_back(rows_.reward.back());
    }
    // qpos / qvel: the joints and the gripper.
    const std::vector<size_t> pos = group_dims(header_.state_names, "joint_pos");
    const std::vector<size_t> vel = group_dims(header_.state_names, "joint_vel");
    const size_t opening = named_dims(header_.state_names, {"gripper.opening"}, path_.string())[0];
    const size_t rate = named_dims(header_.state_names, {"gripper.opening_rate"}, path_.string())[0];
    std::vector<float> qpos, qvel;
    for (int64_t k = 0; k < T; ++k) {
      const float* s = rows_.state.data() + static_cast<size_t>(k) * S;
      for (size_t i : pos) qpos.push_back(s[i]);
      qpos.push_back(s[opening]);
      for (size_t i : vel) qvel.push_back(s[i]);
      qvel.push_back(s[rate]);
    }
    const Hdf5Lock lock(hdf5_mutex());
    for (size_t c = 0; c < images_.size(); ++c) {
      for (int64_t k = frames; k < T; ++k) write_chunk(images_[c], static_cast<hsize_t>(k), last_chunks_[c], path_);
    }
    const hsize_t rows = static_cast<hsize_t>(T);
    const Id observations(H5Gopen2(file_, "observations", H5P_DEFAULT), H5Gclose);
    write_matrix(observations, "qpos", H5T_NATIVE_FLOAT, qpos, rows, path_);
    write_matrix(observations, "qvel", H5T_NATIVE_FLOAT, qvel, rows, path_);
    write_matrix(observations, "state", H5T_NATIVE_FLOAT, rows_.state, rows, path_);
    write_matrix(file_, "action", H5T_NATIVE_FLOAT, rows_.action, rows, path_);
    const Id annotations = create_group(file_, "annotations", path_);
    write_strings(annotations, "human_act", rows_.human_act, path_);
    write_strings(annotations, "events", rows_.events, path_);
    write_vector(annotations, "reward", H5T_NATIVE_FLOAT, rows_.reward, path_);
    write_attribute_bool(file_, "sim", true, path_);
    write_identity(file_, header_, frames, path_);
    write_attribute(file_, "padded_frames", T - frames, path_);
    seal();
  }

 private:
  std::vector<std::vector<uint8_t>> last_chunks_;
};

}  // namespace

fs::path act_episode_path(const fs::path& dir, const std::string& task, int64_t index) {
  return dir / task / fmt::format("episode_{}.hdf5", index);
}

ActWriter::ActWriter(fs::path dir) : dir_(std::move(dir)) {}

std::unique_ptr<EpisodeSink> ActWriter::begin_episode(const EpisodeHeader& header) {
  fs::create_directories(dir_ / header.task);
  return std::make_unique<ActSink>(dir_ / header.task, header);
}

void ActWriter::commit(std::unique_ptr<EpisodeSink> sink, const EpisodeOutcome& outcome) {
  auto* act = dynamic_cast<FileSink*>(sink.get());
  HRIB_CHECK(act != nullptr) << "a sink of another writer";
  const std::string& task = act->header().task;
  act->commit(outcome, act_episode_path(dir_, task, episodes_[task]), "/");
  ++episodes_[task];
}

void ActWriter::discard(std::unique_ptr<EpisodeSink> sink) { sink.reset(); }

void ActWriter::store(std::unique_ptr<EpisodeSink> sink, const fs::path& folder) {
  auto* act = dynamic_cast<ActSink*>(sink.get());
  HRIB_CHECK(act != nullptr) << "a sink of this writer";
  act->store(folder, "act-hdf5");
}

std::unique_ptr<EpisodeSink> ActWriter::load(const fs::path& folder) {
  return load_stored(folder, "act-hdf5", [this](const EpisodeHeader& h) { return dir_ / h.task; }, "episode");
}

void ActWriter::resume(const std::vector<EpisodeHeader>& committed) {
  episodes_.clear();
  for (const EpisodeHeader& h : committed) ++episodes_[h.task];
  std::error_code ec;
  if (!fs::exists(dir_, ec)) return;
  for (const fs::directory_entry& folder : fs::directory_iterator(dir_)) {
    if (!folder.is_directory() || folder.path().filename() == "hribench") continue;
    const std::string task = folder.path().filename().string();
    const int64_t count = episodes_.count(task) ? episodes_.at(task) : 0;
    for (const fs::directory_entry& entry : fs::directory_iterator(folder.path())) {
      const std::string name = entry.path().filename().string();
      int64_t index = -1;
      if (name.starts_with("episode_") && name.ends_with(".hdf5")) index = std::atoll(name.c_str() + 8);
      if (name.ends_with(".tmp") || index >= count) fs::remove(entry.path());
    }
  }
  for (const auto& [task, count] : episodes_) {
    for (int64_t i = 0; i < count; ++i) {
      if (!fs::exists(act_episode_path(dir_, task, i))) {
        throw core::InputError("--resume", act_episode_path(dir_, task, i).string() + " (a committed episode)",
                               "no such file");
      }
    }
  }
}

// ---------------------------------------------------------------------------------------------
// robomimic

std::vector<float> robomimic_action_scale(const std::vector<float>& low, const std::vector<float>& high) {
  std::vector<float> scale;
  for (size_t j = 0; j < low.size(); ++j) {
    const double bound = std::max(std::abs(static_cast<double>(low[j])), std::abs(static_cast<double>(high[j])));
    scale.push_back(static_cast<float>(std::exp2(std::ceil(std::log2(std::max(bound, 1e-30))))));
  }
  return scale;
}

fs::path robomimic_dataset_path(const fs::path& dir) { return dir / "dataset.hdf5"; }

namespace {

fs::path parts_folder(const fs::path& dir) { return dir / "hribench" / "robomimic"; }
fs::path part_path(const fs::path& dir, size_t index) { return parts_folder(dir) / fmt::format("demo_{}.hdf5", index); }

// One demo in its own file (group "demo"), images streamed, the rest written at the last frame.
// images_: the cameras' obs, then their next_obs.
class RobomimicSink : public FileSink {
 public:
  RobomimicSink(const fs::path& folder, EpisodeHeader header, std::vector<float> scale)
      : FileSink(std::move(header), temporary_path(folder, "demo")), scale_(std::move(scale)) {
    const Hdf5Lock lock(hdf5_mutex());
    file_ = create_file(path_);
    const Id demo = create_group(file_, "demo", path_);
    const Id obs = create_group(demo, "obs", path_);
    const Id next_obs = create_group(demo, "next_obs", path_);
    for (const hid_t group : {obs.get(), next_obs.get()}) {
      for (const CameraSpec& c : header_.cameras) {
        const hsize_t H = static_cast<hsize_t>(c.height), W = static_cast<hsize_t>(c.width);
        images_.push_back(
            create_dataset(group, c.name + "_image", H5T_NATIVE_UINT8, {0, H, W, 3}, {1, H, W, 3}, true, true, path_));
      }
    }
  }

  void add(const Frame& f) override {
    check_frame(header_, f, path_);
    std::vector<std::vector<uint8_t>> chunks;
    for (const render::Image* image : f.images) chunks.push_back(deflate_image(*image, path_));
    const hsize_t k = static_cast<hsize_t>(f.index);
    {
      const Hdf5Lock lock(hdf5_mutex());
      // Frame k is obs k (unless it is the last) and next_obs k - 1.
      for (size_t c = 0; c < chunks.size(); ++c) {
        const hsize_t H = static_cast<hsize_t>(header_.cameras[c].height), W = static_cast<hsize_t>(header_.cameras[c].width);
        if (!f.done) {
          const hsize_t dims[4] = {k + 1, H, W, 3};
          check(H5Dset_extent(images_[c], dims), path_, "extend an image dataset");
          write_chunk(images_[c], k, chunks[c], path_);
        }
        if (k > 0) {
          const hsize_t dims[4] = {k, H, W, 3};
          check(H5Dset_extent(images_[chunks.size() + c], dims), path_, "extend an image dataset");
          write_chunk(images_[chunks.size() + c], k - 1, chunks[c], path_);
        }
      }
    }
    rows_.add(f);
    if (f.done) close();
  }

  void close() {
    const size_t S = header_.state_names.size(), A = header_.action_names.size();
    const size_t n = static_cast<size_t>(rows_.frames - 1);  // transitions
    const size_t D = rows_.sim_state.size() / static_cast<size_t>(rows_.frames);
    // Normalised actions: exact (the scales are powers of two).
    std::vector<float> actions(rows_.action.begin(), rows_.action.begin() + static_cast<long>(n * A));
    for (size_t i = 0; i < actions.size(); ++i) actions[i] /= scale_[i % A];
    std::vector<double> rewards(n);
    std::vector<int64_t> dones(n);
    for (size_t k = 0; k < n; ++k) {
      rewards[k] = static_cast<double>(rows_.reward[k + 1]);
      dones[k] = rows_.done[k + 1];
    }
    const std::vector<double> states(rows_.sim_state.begin(), rows_.sim_state.begin() + static_cast<long>(n * D));
    const Hdf5Lock lock(hdf5_mutex());
    const Id demo(H5Gopen2(file_, "demo", H5P_DEFAULT), H5Gclose);
    // Per state group, obs (frames 0 .. n-1) and next_obs (1 .. n).
    for (const std::string& group : groups_of(header_.state_names)) {
      const std::vector<size_t> dims = group_dims(header_.state_names, group);
      std::vector<float> obs, next;
      for (size_t k = 0; k < n; ++k) {
        for (size_t i : dims) obs.push_back(rows_.state[k * S + i]);
        for (size_t i : dims) next.push_back(rows_.state[(k + 1) * S + i]);
      }
      const Id o(H5Gopen2(demo, "obs", H5P_DEFAULT), H5Gclose);
      const Id no(H5Gopen2(demo, "next_obs", H5P_DEFAULT), H5Gclose);
      write_matrix(o, group, H5T_NATIVE_FLOAT, obs, n, path_);
      write_matrix(no, group, H5T_NATIVE_FLOAT, next, n, path_);
    }
    write_matrix(demo, "actions", H5T_NATIVE_FLOAT, actions, n, path_);
    write_vector(demo, "rewards", H5T_NATIVE_DOUBLE, rewards, path_);
    write_vector(demo, "dones", H5T_NATIVE_INT64, dones, path_);
    write_matrix(demo, "states", H5T_NATIVE_DOUBLE, states, n, path_);
    const Id annotations = create_group(demo, "annotations", path_);
    write_strings(annotations, "human_act", std::vector<std::string>(rows_.human_act.begin(), rows_.human_act.end() - 1), path_);
    write_strings(annotations, "events", std::vector<std::string>(rows_.events.begin(), rows_.events.end() - 1), path_);
    write_attribute(demo, "num_samples", static_cast<int64_t>(n), path_);
    write_identity(demo, header_, rows_.frames, path_);
    const nlohmann::json ep_meta = {{"lang", header_.instruction}, {"task", header_.task}, {"task_id", header_.task_id},
                                    {"role", header_.role},        {"seed", header_.seed}, {"spec_hash", header_.spec_hash},
                                    {"policy", header_.policy}};
    write_attribute(demo, "ep_meta", ep_meta.dump(), path_);
    seal();
  }

 private:
  std::vector<float> scale_;
};

}  // namespace

RobomimicWriter::RobomimicWriter(fs::path dir) : dir_(std::move(dir)) {}

std::unique_ptr<EpisodeSink> RobomimicWriter::begin_episode(const EpisodeHeader& header) {
  fs::create_directories(parts_folder(dir_));
  return std::make_unique<RobomimicSink>(parts_folder(dir_), header,
                                         robomimic_action_scale(header.action_low, header.action_high));
}

void RobomimicWriter::commit(std::unique_ptr<EpisodeSink> sink, const EpisodeOutcome& outcome) {
  auto* demo = dynamic_cast<FileSink*>(sink.get());
  HRIB_CHECK(demo != nullptr) << "a sink of another writer";
  demo->commit(outcome, part_path(dir_, tasks_.size()), "demo");
  tasks_.push_back(demo->header().task);
  action_scale_ = robomimic_action_scale(demo->header().action_low, demo->header().action_high);
  action_space_ = demo->header().action_space;
  action_names_ = demo->header().action_names;
}

void RobomimicWriter::discard(std::unique_ptr<EpisodeSink> sink) { sink.reset(); }

void RobomimicWriter::store(std::unique_ptr<EpisodeSink> sink, const fs::path& folder) {
  auto* demo = dynamic_cast<RobomimicSink*>(sink.get());
  HRIB_CHECK(demo != nullptr) << "a sink of this writer";
  demo->store(folder, "robomimic");
}

std::unique_ptr<EpisodeSink> RobomimicWriter::load(const fs::path& folder) {
  return load_stored(folder, "robomimic", [this](const EpisodeHeader&) { return parts_folder(dir_); }, "demo");
}

void RobomimicWriter::resume(const std::vector<EpisodeHeader>& committed) {
  tasks_.clear();
  for (const EpisodeHeader& h : committed) tasks_.push_back(h.task);
  if (!committed.empty()) {
    action_scale_ = robomimic_action_scale(committed.back().action_low, committed.back().action_high);
    action_space_ = committed.back().action_space;
    action_names_ = committed.back().action_names;
  }
  fs::create_directories(parts_folder(dir_));
  // A finished dataset's demos go back into parts (finish() removed them).
  const fs::path final_path = robomimic_dataset_path(dir_);
  if (fs::exists(final_path)) {
    const Hdf5Lock lock(hdf5_mutex());
    const Id file = open_file(final_path, false);
    for (size_t i = 0; i < committed.size(); ++i) {
      if (fs::exists(part_path(dir_, i))) continue;
      const std::string name = fmt::format("data/demo_{}", i);
      if (H5Lexists(file, "data", H5P_DEFAULT) <= 0 || H5Lexists(file, name.c_str(), H5P_DEFAULT) <= 0) continue;
      const fs::path tmp = temporary_path(parts_folder(dir_), "demo");
      {
        const Id part = create_file(tmp);
        check(H5Ocopy(file, name.c_str(), part, "demo", H5P_DEFAULT, H5P_DEFAULT), tmp, "copy " + name);
      }
      fs::rename(tmp, part_path(dir_, i));
    }
  }
  for (const fs::directory_entry& entry : fs::directory_iterator(parts_folder(dir_))) {
    const std::string name = entry.path().filename().string();
    if (name.ends_with(".tmp") || (name.starts_with("demo_") && std::atoll(name.c_str() + 5) >= static_cast<long long>(committed.size()))) {
      fs::remove(entry.path());
    }
  }
  for (size_t i = 0; i < committed.size(); ++i) {
    if (!fs::exists(part_path(dir_, i))) {
      throw core::InputError("--resume", part_path(dir_, i).string() + " (a committed episode)", "no such file");
    }
  }
}

void RobomimicWriter::finish() {
  const fs::path final_path = robomimic_dataset_path(dir_);
  const fs::path tmp = final_path.string() + ".tmp";
  {
    const Hdf5Lock lock(hdf5_mutex());
    const Id file = create_file(tmp);
    const Id data = create_group(file, "data", tmp);
    int64_t total = 0;
    std::map<std::string, std::vector<std::string>> masks;
    for (size_t i = 0; i < tasks_.size(); ++i) {
      const std::string name = fmt::format("demo_{}", i);
      {
        const Id part = open_file(part_path(dir_, i), false);
        check(H5Ocopy(part, "demo", data, name.c_str(), H5P_DEFAULT, H5P_DEFAULT), tmp, "copy " + name);
      }
      const Id demo(H5Gopen2(data, name.c_str(), H5P_DEFAULT), H5Gclose);
      total += read_attribute<int64_t>(demo, "num_samples", H5T_NATIVE_INT64, tmp);
      masks[tasks_[i]].push_back(name);
    }
    write_attribute(data, "total", total, tmp);
    const nlohmann::json env_args = {
        {"env_name", "HRIBench"},
        {"env_version", std::string(core::version())},
        {"type", 2},
        {"env_kwargs",
         {{"action_space", action_space_}, {"action_names", action_names_}, {"action_scale", action_scale_},
          {"control_freq", 20}}}};
    write_attribute(data, "env_args", env_args.dump(), tmp);
    // /mask/TASK: the demos of each task, as fixed-length byte strings (robomimic's filter keys).
    const Id mask = create_group(file, "mask", tmp);
    for (const auto& [task, names] : masks) {
      size_t width = 1;
      for (const std::string& n : names) width = std::max(width, n.size());
      std::vector<char> bytes(names.size() * width, '\0');
      for (size_t i = 0; i < names.size(); ++i) std::memcpy(bytes.data() + i * width, names[i].data(), names[i].size());
      const Id type(H5Tcopy(H5T_C_S1), H5Tclose);
      H5Tset_size(type, width);
      H5Tset_strpad(type, H5T_STR_NULLPAD);
      const Id d = create_dataset(mask, task, type, {names.size()}, {}, false, false, tmp);
      check(H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, bytes.data()), tmp, "write mask " + task);
    }
  }
  fs::rename(tmp, final_path);
  for (size_t i = 0; i < tasks_.size(); ++i) fs::remove(part_path(dir_, i));
}

// ---------------------------------------------------------------------------------------------
// Readers

namespace {

// The identity write_identity wrote (the actions are the caller's).
RecordedEpisode read_identity(hid_t at, const fs::path& file) {
  RecordedEpisode r;
  r.task = read_string_attribute(at, "task", file);
  r.spec_hash = read_string_attribute(at, "spec_hash", file);
  r.seed = read_attribute<uint64_t>(at, "seed", H5T_NATIVE_UINT64, file);
  r.policy = read_string_attribute(at, "policy", file);
  r.action_space = policy::action_space_from_string(read_string_attribute(at, "action_space", file), file.string());
  return r;
}

}  // namespace

std::vector<RecordedEpisode> read_act_episodes(const fs::path& dir, const std::vector<std::string>& tasks) {
  std::vector<RecordedEpisode> out;
  const Hdf5Lock lock(hdf5_mutex());
  for (const std::string& task : tasks) {
    for (int64_t i = 0; fs::exists(act_episode_path(dir, task, i)); ++i) {
      const fs::path path = act_episode_path(dir, task, i);
      const Id file = open_file(path, false);
      RecordedEpisode r = read_identity(file, path);
      const int64_t frames = read_attribute<int64_t>(file, "frames", H5T_NATIVE_INT64, path);
      r.actions = read_rows(file, "action", static_cast<hsize_t>(std::max<int64_t>(frames - 1, 0)), path);
      out.push_back(std::move(r));
    }
  }
  return out;
}

std::vector<RecordedEpisode> read_robomimic_episodes(const fs::path& dir) {
  const fs::path path = robomimic_dataset_path(dir);
  std::vector<RecordedEpisode> out;
  const Hdf5Lock lock(hdf5_mutex());
  const Id file = open_file(path, false);
  const Id data(check_id(H5Gopen2(file, "data", H5P_DEFAULT), path, "find group data"), H5Gclose);
  const nlohmann::json env_args = nlohmann::json::parse(read_string_attribute(data, "env_args", path), nullptr, false);
  if (env_args.is_discarded() || !env_args.contains("env_kwargs") || !env_args["env_kwargs"].contains("action_scale")) {
    throw core::InputError(path.string() + " data.env_args", "JSON with env_kwargs.action_scale", "other");
  }
  const std::vector<float> scale = env_args["env_kwargs"]["action_scale"].get<std::vector<float>>();
  for (size_t i = 0;; ++i) {
    const std::string name = fmt::format("demo_{}", i);
    if (H5Lexists(data, name.c_str(), H5P_DEFAULT) <= 0) break;
    const Id demo(H5Gopen2(data, name.c_str(), H5P_DEFAULT), H5Gclose);
    RecordedEpisode r = read_identity(demo, path);
    const int64_t n = read_attribute<int64_t>(demo, "num_samples", H5T_NATIVE_INT64, path);
    r.actions = read_rows(demo, "actions", static_cast<hsize_t>(n), path);
    for (std::vector<float>& a : r.actions) {
      if (a.size() != scale.size()) {
        throw core::InputError(path.string() + " " + name + "/actions", fmt::format("{} columns (action_scale)", scale.size()),
                               std::to_string(a.size()));
      }
      for (size_t j = 0; j < a.size(); ++j) a[j] *= scale[j];
    }
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace hribench::io
