#!/usr/bin/env bash
# Builds the libFuzzer harnesses of fuzz/ (clang-14, -fsanitize=fuzzer,address,undefined) into
# ${HRIBENCH_FUZZ_DIR:-build-fuzz} and runs each for SECONDS (default 60), one after another,
# starting from its committed seed corpus fuzz/corpus/TARGET (new inputs go to
# build-fuzz/corpus/TARGET). A crash is saved under build-fuzz/crashes/TARGET/ and makes the
# script exit non-zero; per target it prints the executions and the time (docs/hardening.md).
# Needs two Debian packages beyond deps/debian-packages.txt:
#   apt-get install clang-14 libclang-rt-14-dev
# Usage: scripts/fuzz.sh [SECONDS] [TARGET...]   (targets: the fuzz/*_fuzz.cc names)
#   RUNS=10000000 scripts/fuzz.sh 3600 bvh        # stop at 10 million executions (or 3600 s)
#   FORK=2 RUNS=10000000 scripts/fuzz.sh 9000 scenario   # one run on two cores (libFuzzer -fork=2:
#                                                        # child processes, executions summed)
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HRIBENCH_FUZZ_DIR:-$root/build-fuzz}"
seconds="${1:-60}"
shift || true
targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for f in "$root"/fuzz/*_fuzz.cc; do targets+=("$(basename "$f" _fuzz.cc)"); done
fi
CC=clang-14 CXX=clang++-14 cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DHRIBENCH_FUZZ=ON -DHRIBENCH_BUILD_TESTS=OFF -DHRIBENCH_BUILD_BENCH=OFF >/dev/null
cmake --build "$build" --parallel "${JOBS:-2}" --target "${targets[@]/#/fuzz_}"
failed=0
for t in "${targets[@]}"; do
  mkdir -p "$build/corpus/$t" "$build/crashes/$t" "$build/logs"
  log="$build/logs/$t.log"
  # Leaks are not crashes here: MuJoCo's and yaml-cpp's process-lifetime allocations are kept.
  if ! ASAN_OPTIONS="detect_leaks=0:${ASAN_OPTIONS:-}" "$build/fuzz/fuzz_$t" -max_total_time="$seconds" \
      -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 ${RUNS:+-runs=$RUNS} ${FORK:+-fork=$FORK} \
      -artifact_prefix="$build/crashes/$t/" "$build/corpus/$t" "$root/fuzz/corpus/$t" >"$log" 2>&1; then
    failed=1
    echo "$t: CRASH (see $log and $build/crashes/$t/)"
  fi
  if [ -n "${FORK:-}" ]; then  # the parent's last "#RUNS: cov: ..." line and "INFO: exiting: RC time: Ns"
    runs=$(grep -o '^#[0-9]*: cov' "$log" | tail -n 1 | grep -o '[0-9]*' || echo "?")
    time=$(grep -o 'INFO: exiting: [0-9]* time: [0-9]*s' "$log" | grep -o '[0-9]*s$' | grep -o '[0-9]*' || echo "$seconds")
  else
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo "?")
    time=$(grep -o 'Done [0-9]* runs in [0-9]* second' "$log" | grep -o 'in [0-9]*' | grep -o '[0-9]*' || echo "$seconds")
  fi
  echo "$t: $runs executions in ${time} s"
done
exit $failed
