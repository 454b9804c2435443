#!/usr/bin/env bash
# Builds test binaries with AddressSanitizer and UndefinedBehaviorSanitizer
# (-DHRIBENCH_SANITIZE=address,undefined) into ${HRIBENCH_ASAN_DIR:-build-asan} and runs them from
# the repository root; any sanitizer report fails the run (docs/hardening.md).
# Usage: scripts/sanitize-test.sh [TEST_BINARY...] [-- GTEST_ARGS...]
#   scripts/sanitize-test.sh                       # every layer's tests
#   scripts/sanitize-test.sh core_test script_test -- --gtest_filter=-*Slow*
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HRIBENCH_ASAN_DIR:-$root/build-asan}"
tests=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do tests+=("$1"); shift; done
[ "${1:-}" = "--" ] && shift
if [ ${#tests[@]} -eq 0 ]; then
  tests=(core_test human_test script_test model_test sim_test render_test policy_test remote_test eval_test gen_test io_test cli_test)
fi
launcher=()
command -v ccache >/dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DHRIBENCH_SANITIZE=address,undefined \
  -DHRIBENCH_BUILD_BENCH=OFF "${launcher[@]}" >/dev/null
targets=("${tests[@]}")
# The eval (MPI ranks), io and cli tests run the command itself.
[[ " ${tests[*]} " =~ " "(eval|io|cli)_test" " ]] && targets+=(hribench)
cmake --build "$build" --parallel "${JOBS:-2}" --target "${targets[@]}"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0:abort_on_error=1:strict_string_checks=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
cd "$root"
failed=()
for t in "${tests[@]}"; do
  echo "== $t"
  "$build/tests/$t" "$@" || failed+=("$t")
done
if [ ${#failed[@]} -gt 0 ]; then
  echo "failed under ASan/UBSan: ${failed[*]}"
  exit 1
fi
echo "all passed under ASan/UBSan: ${tests[*]}"
