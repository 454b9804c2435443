#!/usr/bin/env bash
# Regenerates the pictures of the report page and of a replay frame (docs/report.md, README)
# into docs/images/report.png and docs/images/replay.png: the browser tests (tests/web/) make
# their small run, open its pages in Chromium and save what the browser shows.
#
# Usage: scripts/render-report-pictures.sh [OUT_DIR]   (default docs/images)
# HRIBENCH names the binary (default ${HRIBENCH_BUILD_DIR:-build}/hribench); the replay test
# reads the log through the Python module of the same build folder.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
build="${HRIBENCH_BUILD_DIR:-build}"
export HRIBENCH_BINARY="${HRIBENCH:-$build/hribench}"
export HRIBENCH_PYTHONPATH="${HRIBENCH_PYTHONPATH:-$build/python}"
export HRIBENCH_DOC_PICTURES="${1:-docs/images}"
node tests/web/report_page_test.mjs
node tests/web/replay_page_test.mjs
