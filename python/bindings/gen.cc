// gen (and script): the episodes an environment is made of — a task's script sampled with a
// seed, or an episode of a generated pool's split (gen/pool.h) — as opaque EpisodeSpecs.
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "bindings.h"
#include "core/errors.h"
#include "core/paths.h"
#include "gen/evaluation.h"
#include "gen/pool.h"
#include "policy/registry.h"
#include "script/check.h"
#include "script/sample.h"
#include "script/scenario.h"

namespace py = pybind11;

namespace hribench::python {

void bind_gen(py::module_& m) {
  py::class_<script::EpisodeSpec>(m, "EpisodeSpec", "A sampled episode (script/scenario.h).")
      .def_readonly("task", &script::EpisodeSpec::task)
      .def_readonly("role", &script::EpisodeSpec::role)
      .def_readonly("seed", &script::EpisodeSpec::seed)
      .def_readonly("variant", &script::EpisodeSpec::variant)
      .def_readonly("instruction", &script::EpisodeSpec::instruction)
      .def_readonly("horizon", &script::EpisodeSpec::horizon)
      .def_readonly("robot", &script::EpisodeSpec::robot)
      .def_property_readonly("hash", [](const script::EpisodeSpec& s) { return script::spec_hash(s); })
      .def("__repr__", [](const script::EpisodeSpec& s) {
        return "<EpisodeSpec " + s.task + " seed " + std::to_string(s.seed) + ">";
      });
  m.def(
      "sample_task",
      [](const std::string& task, uint64_t seed) {
        const std::vector<std::string> files = gen::resolve_task_scripts(task);
        if (files.size() != 1) throw core::InputError("task", "one task", "'" + task + "'");
        return script::sample(script::load_scenario(core::resolve_data_path(files[0]).string()), seed);
      },
      py::arg("task"), py::arg("seed"),
      "The episode of a task (id, name or script file) sampled with `seed`.");
  m.def(
      "pool_episodes",
      [](const std::string& pool, const std::string& split, const std::vector<std::string>& tasks) {
        return gen::pool_episodes(gen::read_manifest(pool), gen::split_from_name(split, "split"), tasks);
      },
      py::arg("pool"), py::arg("split") = "eval", py::arg("tasks") = std::vector<std::string>{},
      "The episodes of a pool's split (all tasks, or those named), re-sampled and checked.");
  // The run of `hribench eval` (gen/evaluation.h) for one policy: a C++ reference (instances
  // None) or a Python policy, `instances()` -> (PolicySpec, reset or None, act) making one
  // instance per call (python/hribench/evaluate.py). The GIL is released for the run and taken
  // by the policy's calls.
  m.def(
      "evaluate",
      [](const std::string& name, const py::object& instances, const std::string& tasks,
         const std::string& out, const std::string& pool, const std::string& split, int episodes,
         uint64_t seed, bool sampling_flags, int threads, const std::string& latency, double horizon,
         bool resume, bool force, bool save_logs) {
        gen::EvalRequest r;
        r.tasks = tasks;
        r.policies = name;
        r.out = out;
        r.pool = pool;
        r.split = split;
        r.episodes = episodes;
        r.seed = seed;
        r.sampling_flags = sampling_flags;
        r.threads = threads;
        r.latency = latency;
        r.horizon = horizon;
        r.resume = resume;
        r.force = force;
        r.save_logs = save_logs;
        const py::object* maker = &instances;
        const eval::PolicyMaker make = [maker, name](const std::string& reference) {
          if (maker->is_none() || reference != name) return policy::make_policy(reference);
          py::gil_scoped_acquire gil;
          std::string failure;
          try {
            const py::tuple made = (*maker)();
            return python_policy(made[0].cast<policy::PolicySpec>(), made[1], made[2]);
          } catch (py::error_already_set& e) {
            failure = std::string(py::str(e.value()));
          }
          throw policy::PolicyError(policy::PolicyErrorKind::kFailed, failure);
        };
        py::gil_scoped_release release;
        gen::run_evaluation(r, make);
      },
      py::arg("name"), py::arg("instances"), py::kw_only(), py::arg("tasks"), py::arg("out"),
      py::arg("pool"), py::arg("split"), py::arg("episodes"), py::arg("seed"),
      py::arg("sampling_flags"), py::arg("threads"), py::arg("latency"), py::arg("horizon"),
      py::arg("resume"), py::arg("force"), py::arg("save_logs"));
  m.def("task_names", [] {
    std::vector<std::string> names;
    for (const gen::TaskFile& t : gen::task_catalogue()) names.push_back(t.name);
    return names;
  });
}

}  // namespace hribench::python
