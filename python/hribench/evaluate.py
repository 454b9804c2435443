"""hribench.evaluate: Python policies in the benchmark (docs/python.md). The run is the C++
one of `hribench eval` (src/eval/run.h): the same jobs, workers, files, resume and results."""

import copy
import threading

from . import _hribench
from .results import load_results


def _as_spec(spec):
    if isinstance(spec, _hribench.PolicySpec):
        return spec
    if isinstance(spec, dict):
        return _hribench.PolicySpec(**spec)
    raise TypeError(f"spec(): expected a hribench.PolicySpec or a dict of its arguments, got {spec!r}")


def _policy_name(policy, name):
    if name is not None:
        return str(name)
    if hasattr(policy, "name"):
        return str(policy.name)
    if hasattr(policy, "__name__"):
        return str(policy.__name__)
    return type(policy).__name__.lower()


class _Instances:
    """Makes one policy instance per worker thread, as the CLI does: the object itself for
    the first worker, a copy.deepcopy of it for each further one (reset() starts every episode,
    so results do not depend on which instance runs an episode). The first call is the run's
    check of its policies (gen::plan_evaluation makes each once before the run): the object
    itself too."""

    def __init__(self, policy, spec):
        self.policy = policy
        self.spec = spec
        self.made = 0
        self.lock = threading.Lock()

    def __call__(self):
        with self.lock:
            instance = self.policy if self.made < 2 else copy.deepcopy(self.policy)
            self.made += 1
        if callable(instance) and not hasattr(instance, "act"):
            return self.spec, None, instance
        return self.spec, getattr(instance, "reset", None), instance.act


def evaluate(policy, tasks="all", *, out, pool=None, split="eval", episodes=None, seed=None,
             threads=1, latency="none", horizon=None, resume=False, force=False, save_logs=False,
             name=None, spec=None):
    """Runs `policy` on the tasks' episodes and scores them, writing OUT as `hribench eval`
    does (options.json, episodes.jsonl as episodes finish, results.json, summary.md,
    summary.csv, report.html; logs/ with save_logs); returns the results as rows (load_results(out, dataframe=False)).

    policy: an object with spec() -> hribench.PolicySpec (or a dict of its arguments),
    reset(info) and act(obs) -> an action (dim,) or a chunk (n, dim); or a callable obs ->
    action (with `spec`, default ee_delta without cameras); or the reference of a C++ policy
    ("noop", "oracle", ...). name: the policy's name in the results (default its `name`
    attribute, or its function or class name). Other arguments are the CLI's flags: episodes
    and seed sample each task's script (default 10 from seed 0); pool and split take a pool's
    episodes instead. threads: worker threads; physics runs with the GIL released, calls into
    the policy take it. A Python exception in reset or act ends that episode with status
    policy_error and the exception's type and message as the reason.
    """
    if isinstance(policy, str):
        entry = (policy, None)
    else:
        if spec is None:
            if hasattr(policy, "spec"):
                spec = policy.spec()
            elif callable(policy):
                spec = _hribench.PolicySpec()
            else:
                raise TypeError("policy: expected an object with spec/reset/act, a callable or a "
                                f"policy reference, got {type(policy).__name__}")
        if not hasattr(policy, "act") and not callable(policy):
            raise TypeError(f"policy: expected an object with act(obs) or a callable, got {type(policy).__name__}")
        policy_name = _policy_name(policy, name)
        if not policy_name or "," in policy_name:
            raise ValueError(f"name: expected a policy name without commas, got '{policy_name}'")
        entry = (policy_name, _Instances(policy, _as_spec(spec)))
    _hribench.evaluate(
        entry[0], entry[1], tasks=str(tasks), out=str(out), pool="" if pool is None else str(pool),
        split=split, episodes=10 if episodes is None else int(episodes),
        seed=0 if seed is None else int(seed), sampling_flags=episodes is not None or seed is not None,
        threads=int(threads), latency=str(latency), horizon=-1.0 if horizon is None else float(horizon),
        resume=bool(resume), force=bool(force), save_logs=bool(save_logs))
    return load_results(out, dataframe=False)
