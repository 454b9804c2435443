#!/usr/bin/env bash
# The README's main command: install, build, then run the main job and write its outputs
# under ${HRIBENCH_OUT:-out/}. Until the evaluation lands (issue 5), the main job renders the
# scene and runs the speed benchmark.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HRIBENCH_BUILD_DIR:-$root/build}"
out="${HRIBENCH_OUT:-$root/out}"
HRIBENCH_BUILD_DIR="$build" bash "$root/scripts/build.sh"
mkdir -p "$out"
"$build/hribench" version
"$build/hribench" render --out "$out/scene.png"
"$build/hribench" bench --json "$out/bench.json"
echo "main: wrote $out/scene.png and $out/bench.json"
