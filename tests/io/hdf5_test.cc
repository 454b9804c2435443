// Tests of the HDF5 datasets (io/hdf5.h) on a small collect of each format (two tasks, one
// episode each, 32x32 images, two threads): h5py (Debian's python3-h5py) reads every file and
// checks what ACT's and robomimic's loaders require (shapes, dtypes, attributes, equal lengths
// per task, actions in [-1, 1], next_obs one frame on); the episodes read back with libhdf5
// replay to logs identical, bit for bit, to the collect's.

#include "io/hdf5.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "gen/pool.h"
#include "io/collect.h"
#include "io/replay.h"
#include "script/sample.h"
#include "support/test_files.h"

namespace hribench::io {
namespace {

namespace fs = std::filesystem;

struct PythonResult {
  int exit_code = -1;
  std::string output;
};

// Runs a Python program with Debian's interpreter (the one that sees python3-h5py).
PythonResult run_python(const std::string& program, const std::string& argument) {
  const fs::path file = fs::path(::testing::TempDir()) / ("hribench_hdf5_check_" + std::to_string(getpid()) + ".py");
  std::ofstream(file) << program;
  PythonResult result;
  FILE* pipe = popen(("/usr/bin/python3 " + file.string() + " '" + argument + "' 2>&1").c_str(), "r");
  char buffer[4096];
  while (pipe != nullptr && fgets(buffer, sizeof buffer, pipe) != nullptr) result.output += buffer;
  result.exit_code = pipe != nullptr ? WEXITSTATUS(pclose(pipe)) : -1;
  return result;
}

CollectSummary small_collect(const std::string& dir, const std::string& format) {
  CollectRequest r;
  r.tasks = "handover_r2h,stop_go";
  r.episodes = 1;
  r.size = 32;
  r.threads = 2;
  r.format = format;
  r.out = dir;
  return collect(r);
}

// Each format's small collect, made once per process on first use (ctest runs each test in
// its own process: it makes only the collect the test reads).
class Hdf5DatasetTest : public ::testing::Test {
 protected:
  static const std::string& dataset(const std::string& format) {
    static std::map<std::string, std::string> dirs;
    if (dirs.count(format) == 0) {
      dirs[format] = ::hribench::testing::temp_dir("hdf5", format);
      small_collect(dirs[format], format);
    }
    return dirs[format];
  }
  static const std::string& act() { return dataset("act-hdf5"); }
  static const std::string& robomimic() { return dataset("robomimic"); }
};

// What ACT's utils.py load_data / EpisodicDataset read, and our annotations.
const char* kActCheck = R"(
import glob, json, os, sys
import h5py, numpy as np
root = sys.argv[1]
lengths = {}
for task in sorted(os.listdir(root)):
    if task == 'hribench': continue
    files = sorted(glob.glob(os.path.join(root, task, '*.hdf5')))
    assert [os.path.basename(f) for f in files] == ['episode_%d.hdf5' % i for i in range(len(files))], files
    for f in files:
        with h5py.File(f, 'r') as h:
            assert h.attrs['sim'] == True and isinstance(h.attrs['sim'], np.bool_), h.attrs['sim']
            T = h['/action'].shape[0]
            lengths.setdefault(task, set()).add(T)
            frames = int(h.attrs['frames']); padded = int(h.attrs['padded_frames'])
            assert frames + padded == T and frames > 1, (frames, padded, T)
            qpos = h['/observations/qpos']; qvel = h['/observations/qvel']; action = h['/action']
            assert qpos.dtype == np.float32 and qvel.dtype == np.float32 and action.dtype == np.float32
            assert qpos.shape == (T, 8) and qvel.shape == (T, 8) and action.shape == (T, 7), (qpos.shape, action.shape)
            names = json.loads(h.attrs['state_names'])
            state = h['/observations/state'][()]
            assert state.shape == (T, len(names))
            assert np.array_equal(qpos[:, :7], state[:, :7])
            assert np.array_equal(qpos[:, 7], state[:, names.index('gripper.opening')])
            # The measured opening: 0 closed, 1 the full opening (the fingers' slack allows a few %).
            assert -0.05 <= qpos[:, 7].min() and qpos[:, 7].max() <= 1.05, (qpos[:, 7].min(), qpos[:, 7].max())
            for cam in ['agentview', 'wrist']:
                img = h['/observations/images/' + cam]
                assert img.dtype == np.uint8 and img.shape == (T, 32, 32, 3) and img.chunks == (1, 32, 32, 3), img
                pixels = img[()]
                assert pixels.std() > 0
                # The padding holds the final frame.
                assert (pixels[frames:] == pixels[frames - 1]).all()
            assert (state[frames:] == state[frames - 1]).all() and (action[frames:] == action[frames - 1]).all()
            assert h['/annotations/human_act'].shape == (T,) and h['/annotations/reward'].shape == (T,)
            assert h.attrs['success'] == True and isinstance(json.loads(h.attrs['failure_labels']), list)
            assert h.attrs['instruction'] and len(h.attrs['spec_hash']) == 64 and h.attrs['seed'] > 0
            assert any(e for e in h['/annotations/events'].asstr()[()]), 'no cue or act event'
for task, ls in lengths.items():
    assert len(ls) == 1, (task, ls)
assert sorted(lengths) == ['handover_r2h', 'stop_go'], lengths
print('ok', {t: list(l) for t, l in lengths.items()})
)";

TEST_F(Hdf5DatasetTest, ActFilesHoldWhatActsLoaderReads) {
  const PythonResult r = run_python(kActCheck, act());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // The task's horizon: stop_go's 35 s at 20 Hz.
  EXPECT_NE(r.output.find("'stop_go': [701]"), std::string::npos) << r.output;
}

// What robomimic's dataset tools and SequenceDataset read.
const char* kRobomimicCheck = R"(
import json, sys
import h5py, numpy as np
with h5py.File(sys.argv[1] + '/dataset.hdf5', 'r') as h:
    data = h['data']
    env_args = json.loads(data.attrs['env_args'])
    assert isinstance(env_args['type'], int) and env_args['env_name'] == 'HRIBench', env_args
    assert isinstance(env_args['env_kwargs'], dict)
    scale = env_args['env_kwargs']['action_scale']
    demos = sorted(data.keys(), key=lambda d: int(d[5:]))
    assert demos == ['demo_0', 'demo_1'], demos
    total = 0
    for d in demos:
        g = data[d]
        n = int(g.attrs['num_samples'])
        total += n
        a = g['actions'][()]
        assert a.dtype == np.float32 and a.shape == (n, 7) and np.abs(a).max() <= 1.0, (a.shape, np.abs(a).max())
        assert g['rewards'].shape == (n,) and g['dones'].shape == (n,)
        assert g['dones'][-1] == 1 and g['dones'][:-1].sum() == 0
        assert g['states'].ndim == 2 and g['states'].shape[0] == n and g['states'].dtype == np.float64
        assert set(g['obs'].keys()) == set(g['next_obs'].keys()), (list(g['obs']), list(g['next_obs']))
        for key in g['obs']:
            o, no = g['obs'][key][()], g['next_obs'][key][()]
            assert o.shape[0] == n and no.shape == o.shape, (key, o.shape, no.shape)
            assert np.array_equal(o[1:], no[:-1]), key
        img = g['obs/agentview_image']
        assert img.dtype == np.uint8 and img.shape == (n, 32, 32, 3)
        assert g['obs/joint_pos'].shape == (n, 7) and g['obs/gripper'].shape == (n, 2)
        meta = json.loads(g.attrs['ep_meta'])
        assert meta['lang'] == g.attrs['instruction'] and meta['seed'] == g.attrs['seed']
        assert g.attrs['success'] == True
        assert g['rewards'][-1] == 1.0
    assert data.attrs['total'] == total
    masks = {k: [x.decode() for x in h['mask'][k][()]] for k in h['mask']}
    assert sorted(sum(masks.values(), [])) == demos, masks
print('ok', total)
)";

TEST_F(Hdf5DatasetTest, RobomimicFileHoldsWhatRobomimicReads) {
  const PythonResult r = run_python(kRobomimicCheck, robomimic());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(fs::path(robomimic()) / "hribench" / "robomimic" / "demo_0.hdf5"));  // copied, removed
}

// The actions read back with libhdf5 replay (replay_dataset: each episode's spec from the pool,
// its log compared with the one the collect saved).
void expect_replays_identically(const std::string& dir) {
  const std::vector<RecordedEpisode> episodes = read_recorded_episodes(dir);
  ASSERT_EQ(episodes.size(), 2u);
  for (const RecordedEpisode& recorded : episodes) {
    const eval::EpisodeLog saved =
        eval::load_episode_log(collect_log_path(dir, recorded.task, recorded.seed, recorded.spec_hash));
    EXPECT_EQ(saved.steps.size(), recorded.actions.size() + 1);
  }
  const ReplayReport report = replay_dataset(dir);
  EXPECT_EQ(report.episodes, 2u);
  EXPECT_EQ(report.identical, 2u);
  EXPECT_TRUE(report.differing.empty());
}

TEST_F(Hdf5DatasetTest, ActEpisodesReplayToTheirLogsBitForBit) { expect_replays_identically(act()); }
TEST_F(Hdf5DatasetTest, RobomimicEpisodesReplayToTheirLogsBitForBit) { expect_replays_identically(robomimic()); }

TEST_F(Hdf5DatasetTest, OneThreadWritesTheSameBytesAsTwo) {
  const std::string dir = ::hribench::testing::temp_dir("hdf5", "act_one_thread");
  CollectRequest r;
  r.tasks = "handover_r2h,stop_go";
  r.episodes = 1;
  r.size = 32;
  r.threads = 1;
  r.format = "act-hdf5";
  r.out = dir;
  collect(r);
  for (const std::string task : {"handover_r2h", "stop_go"}) {
    const std::string one = ::hribench::testing::read_text(act_episode_path(dir, task, 0));
    EXPECT_FALSE(one.empty());
    EXPECT_TRUE(one == ::hribench::testing::read_text(act_episode_path(act(), task, 0))) << task;
  }
}

TEST(RobomimicActionScale, IsAPowerOfTwoAtLeastTheBound) {
  EXPECT_EQ(robomimic_action_scale({-0.05f, -0.25f, 0.0f, -2.9f}, {0.05f, 0.25f, 1.0f, 2.9f}),
            (std::vector<float>{0.0625f, 0.25f, 1.0f, 4.0f}));
}

TEST(Hdf5StoredEpisode, ALoadOfAFolderWithoutOneOfItsFormatIsRefused) {
  const fs::path dir = ::hribench::testing::temp_dir("hdf5", "stored");
  const fs::path folder = dir / "stored";
  EXPECT_EQ(::hribench::testing::error_of([&] { ActWriter(dir / "act").load(folder); }),
            (folder / "episode.json").string() + ": cannot open file");
  fs::create_directories(folder);
  std::ofstream(folder / "episode.json") << R"({"format": "lerobot"})";
  EXPECT_EQ(::hribench::testing::error_of([&] { ActWriter(dir / "act").load(folder); }),
            (folder / "episode.json").string() + ": expected an episode stored by the act-hdf5 writer, got other JSON");
  std::ofstream(folder / "episode.json", std::ios::trunc) << R"({"format": "robomimic", "header": {"task": 3}})";
  EXPECT_EQ(::hribench::testing::error_of([&] { RobomimicWriter(dir / "robomimic").load(folder); }),
            (folder / "episode.json").string() + ": header.task: expected a string, got number");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hribench::io
