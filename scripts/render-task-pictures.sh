#!/usr/bin/env bash
# Renders the 13 task pictures of docs/tasks.md into docs/images/tasks/<ID>.png: one key moment
# of one sampled episode per task (`hribench render --task`, docs/rendering.md "Task pictures"),
# and the same moment as a policy sees it, the 224x224 agentview frame, into
# docs/images/tasks/agentview-224/<ID>.png. Deterministic: the same build renders the same
# pictures.
#
# Usage: scripts/render-task-pictures.sh [OUT_DIR]   (default docs/images/tasks)
# HRIBENCH names the binary (default ${HRIBENCH_BUILD_DIR:-build}/hribench).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
hribench="${HRIBENCH:-${HRIBENCH_BUILD_DIR:-build}/hribench}"
out="${1:-docs/images/tasks}"
mkdir -p "$out/agentview-224"

# picture ID TASK_FILE SEED POLICY MOMENT [extra render options]
picture() {
  local id="$1" task="$2" seed="$3" policy="$4" at="$5"
  shift 5
  "$hribench" render --task "tasks/$task.yaml" --seed "$seed" --policy "$policy" --at "$at" \
    --camera free --pretty --width 480 --height 360 --out "$out/$id.png" "$@"
  "$hribench" render --task "tasks/$task.yaml" --seed "$seed" --policy "$policy" --at "$at" \
    --camera agentview --width 224 --height 224 --out "$out/agentview-224/$id.png"
}

picture I1 I1_point_pick           1 noop   point.hold+0.3
picture I2 I2_gesture_delivery     1 oracle ask.gesture+0.3
picture I3 I3_demo_imitate         0 noop   demo.transport+0.5
picture I4 I4_stop_go              2 oracle halt.hold+0.3
picture I5 I5_contradiction        0 oracle point_tray.hold+0.2
picture C1 C1_handover_h2r         0 oracle offer.hold_stable+1
picture C2 C2_handover_r2h         0 oracle take.close
picture C3 C3_box_retrieval        0 oracle lid.hold+1
picture C4 C4_co_lift              0 oracle hlift.lift+0.5
picture X1 X1_intrusion_yield      0 oracle intrude.dwell+0.2
picture X2 X2_object_moved         0 oracle relocate.transport+0.4
picture X3 X3_someone_else_places  0 oracle do_it.transport+0.3
picture X4 X4_blocked_target       0 oracle block.dwell+0.3
