#!/usr/bin/env bash
# The README's main command: install, build, then run the main job and write its outputs
# under ${HRIBENCH_OUT:-out/}: validate the 13 task scripts, evaluate the built-in reference
# policies (the oracle expert, the reactive and blind baselines, noop) on the held-out eval split
# of the released episode pool (pool/v8, benchmark version 7; see docs/generation.md) with
# every episode's log, make the video and the 3D replay of the first failed episode of each task
# and policy and rewrite the report page to link them (docs/report.md), render the scene and
# run the speed benchmark.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${HRIBENCH_BUILD_DIR:-$root/build}"
out="${HRIBENCH_OUT:-$root/out}"
HRIBENCH_BUILD_DIR="$build" bash "$root/scripts/build.sh"
mkdir -p "$out"
cd "$root"
"$build/hribench" version
"$build/hribench" check tasks/*.yaml
"$build/hribench" eval --pool "${HRIBENCH_POOL:-pool/v8}" --split eval \
  --policy oracle,reactive,blind,noop --threads "$(nproc)" --save-logs --out "$out/run" --force
"$build/hribench" video "$out/run" --failures 1
"$build/hribench" replay-html "$out/run" --failures 1
"$build/hribench" report "$out/run" --format html
"$build/hribench" render --out "$out/scene.png" --width 640 --height 480
"$build/hribench" bench --json "$out/bench.json"
echo "main: wrote $out/run/{results.json,summary.md,summary.csv,report.html,logs/,videos/,replay/}, $out/scene.png and $out/bench.json"
