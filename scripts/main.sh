#!/usr/bin/env bash
# The README's main command: install, build, then run the main job and write its outputs
# under ${HRIBENCH_OUT:-out/}: validate the 13 task scripts, evaluate the built-in policies on
# them (a few sampled episodes per task until the released episode pool and the oracle land),
# render the scene and run the speed benchmark.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HRIBENCH_BUILD_DIR:-$root/build}"
out="${HRIBENCH_OUT:-$root/out}"
HRIBENCH_BUILD_DIR="$build" bash "$root/scripts/build.sh"
mkdir -p "$out"
cd "$root"
"$build/hribench" version
"$build/hribench" check tasks/*.yaml
"$build/hribench" eval --tasks all --policy noop,random --episodes 3 --threads "$(nproc)" \
  --out "$out/run" --force
"$build/hribench" render --out "$out/scene.png" --width 640 --height 480
"$build/hribench" bench --json "$out/bench.json"
echo "main: wrote $out/run/{results.json,summary.md,summary.csv}, $out/scene.png and $out/bench.json"
