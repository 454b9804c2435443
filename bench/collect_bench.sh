#!/usr/bin/env bash
# The cost of `hribench collect` (docs/datasets.md "Cost"): the same rollouts with two 224-pixel
# cameras on all cores (1) rendered without writing (--dry-run), (2) written as a LeRobot v2.1
# dataset, and (3) the frames of the dataset's videos encoded again by the ffmpeg command line
# with the VideoWriter's codec settings (libx264, veryfast, CRF 23, a key frame every 20 frames,
# no B-frames, one thread, yuv420p). Prints CPU seconds (user + system) and wall seconds of each,
# and the two ratios the issue sets goals for: collect / dry run (goal <= 1.3) and the writing's
# own cost (collect - dry run) / ffmpeg's encode (goal <= 1.2). CPU seconds are the steadier
# figure on a shared machine.
#
# Usage: bench/collect_bench.sh [TASKS] [EPISODES]   (default I1,C2 and 1 episode per task)
# HRIBENCH names the binary (default ${HRIBENCH_BUILD_DIR:-build}/hribench).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
hribench="${HRIBENCH:-${HRIBENCH_BUILD_DIR:-build}/hribench}"
tasks="${1:-I1,C2}"
episodes="${2:-1}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
TIMEFORMAT='%U %S %R'

# cost NAME COMMAND...: runs the command, prints "NAME cpu wall" and keeps cpu in $cpu.
cost() {
  local name="$1"
  shift
  local times
  times="$( { time "$@" > "$tmp/$name.out" 2>&1; } 2>&1 )"
  cpu="$(awk '{printf "%.2f", $1 + $2}' <<<"$times")"
  printf '%-22s %8s s CPU %8s s wall\n' "$name" "$cpu" "$(awk '{print $3}' <<<"$times")"
}

common=(collect --pool pool/v8 --split adapt --policy oracle --cameras agentview,wrist --size 224
        --tasks "$tasks" --episodes "$episodes" --threads "$(nproc)")
cost dry-run "$hribench" "${common[@]}" --dry-run --out "$tmp/dry"
dry="$cpu"
cost collect-lerobot "$hribench" "${common[@]}" --format lerobot --out "$tmp/lerobot"
collect="$cpu"

# The same frames as raw RGB (decoding is not timed), then encoded by ffmpeg.
mkdir -p "$tmp/raw" "$tmp/ffmpeg"
n=0
frames=0
while IFS= read -r video; do
  n=$((n + 1))
  ffmpeg -nostdin -v error -i "$video" -f rawvideo -pix_fmt rgb24 "$tmp/raw/$n.rgb"
  frames=$((frames + $(stat -c %s "$tmp/raw/$n.rgb") / (224 * 224 * 3)))
done < <(find "$tmp/lerobot/videos" -name '*.mp4' | sort)
encode_all() {
  for raw in "$tmp"/raw/*.rgb; do
    ffmpeg -nostdin -v error -y -f rawvideo -pix_fmt rgb24 -s 224x224 -r 20 -i "$raw" -c:v libx264 \
      -preset veryfast -crf 23 -g 20 -bf 0 -threads 1 -pix_fmt yuv420p \
      "$tmp/ffmpeg/$(basename "$raw" .rgb).mp4"
  done
}
cost ffmpeg-encode encode_all
ffmpeg_cpu="$cpu"

echo "frames: $frames in $n videos"
awk -v c="$collect" -v d="$dry" -v f="$ffmpeg_cpu" 'BEGIN {
  printf "collect / dry run: %.2f (goal <= 1.3)\n", c / d
  printf "writing (collect - dry run) / ffmpeg encode: %.2f (goal <= 1.2)\n", (c - d) / f
}'
