#!/usr/bin/env bash
# The README's test command: install, build with warnings as errors, run the whole suite.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HRIBENCH_BUILD_DIR:-$root/build}"
HRIBENCH_BUILD_DIR="$build" bash "$root/scripts/build.sh" -DHRIBENCH_WERROR=ON
cd "$build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
