#!/usr/bin/env bash
# Renders docs/images/video-frame.png, the picture of docs/videos.md: the I4 stop_go noop
# episode of seed 0 made into a video (`eval --video failures`, agentview and wrist cameras),
# and its frame at 8 s decoded by ffmpeg. Deterministic: the same build gives the same picture.
#
# Usage: scripts/render-video-frame.sh [OUT_PNG]   (default docs/images/video-frame.png)
# HRIBENCH names the binary (default ${HRIBENCH_BUILD_DIR:-build}/hribench).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
hribench="${HRIBENCH:-${HRIBENCH_BUILD_DIR:-build}/hribench}"
out="${1:-docs/images/video-frame.png}"
run="$(mktemp -d)"
trap 'rm -rf "$run"' EXIT
"$hribench" eval --tasks I4 --policy noop --episodes 1 --seed 0 --video failures \
  --video-cameras agentview,wrist --out "$run/run" > /dev/null
video="$(ls "$run"/run/videos/*.mp4)"
ffmpeg -v error -y -ss 8 -i "$video" -frames:v 1 -f image2 -c:v png "$run/frame.png"
mkdir -p "$(dirname "$out")"
mv "$run/frame.png" "$out"
echo "render-video-frame: wrote $out from $(basename "$video")"
