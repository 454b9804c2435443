#!/usr/bin/env bash
# The README's main command: install, build, then run the main job and write its outputs
# under ${HRIBENCH_OUT:-out/}. Until evaluation on the released pool lands (issues 5-7), the
# main job validates the task scripts, renders the scene and runs the speed benchmark.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HRIBENCH_BUILD_DIR:-$root/build}"
out="${HRIBENCH_OUT:-$root/out}"
HRIBENCH_BUILD_DIR="$build" bash "$root/scripts/build.sh"
mkdir -p "$out"
cd "$root"
"$build/hribench" version
"$build/hribench" check tasks/*.yaml
"$build/hribench" render --out "$out/scene.png" --width 640 --height 480
"$build/hribench" bench --json "$out/bench.json"
echo "main: wrote $out/scene.png and $out/bench.json"
