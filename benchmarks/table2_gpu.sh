#!/usr/bin/env bash
# Table 2 in one go on a machine with one GPU (issues 29 and 40): the synthetic tree of experiment=table2_large,
# every run side by side on the one GPU (one CPU thread each), then sdn3d-table2.
#
#   bash benchmarks/table2_gpu.sh OUT_DIR
#
# The tree (issue 40: enough objects that training stops over-fitting): sdn3d-synth with 30 worlds (the five
# Virtual KITTI names and 25 drawn from the seed) x 4 variations (clone, sunset, fog, rain) x 20 frames, no edit
# pairs, camera heights drawn per world; about 2,400 frames at 624x192.
# Runs (experiment=table2_large: 6 L_pred + 3 joint epochs, validation every epoch; each fit capped at $MAX_TIME,
# then tested on the checkpoint validation selected):
#   SET=core (default): full and no_reproj at seeds 0 1 2, full_multibin at seed 0 (7 runs; the joint stage's
#                       exact policy gradient renders all 8 templates per object, so each joint run weighs most)
#   SET=all:            also full_multibin at seeds 1 2, deep3dbox, full_quaternion, no_tau and single_cad at seed 0
#                       (13 runs)
# OUT_DIR gets: device.txt, timing.txt (each phase's seconds and the tree's size), runs.jsonl (every run's summary),
# table2.md / table2.json, logs.txt (errors and the end of each run's log), epochs.txt (each run's per-epoch lines:
# seconds, losses, validation figures).
# Stopped (a `timeout` around it, a lease's end: SIGTERM or SIGINT), it still writes what it has: the summaries of
# the runs that finished, every run's per-epoch lines and log ends, and the table of the finished runs; a run
# stopped while testing can be tested later with `sdn3d-train resume=<its run dir>` (docs/TRAINING.md).
# Measured on one H200 (docs/results/2026-11-30_h200/table2_large/): the tree 85 s; the 7 fits 165 s (w/o L_reproj)
# to 365 s (full: the joint stage's epochs take ~80 s each, 4 runs in it at once); the tests 140-220 s (the
# test-time fit's row included). A 10-minute call therefore needs DEADLINE: the seconds the whole script may take;
# each fit then gets what is left after the tree and TEST_RESERVE seconds (200) for the tests.
# Environment: PYTHON (python3), DEADLINE (unset: no deadline), MAX_TIME (each run's trainer.max_time when DEADLINE
# is unset, 00:00:06:00), TEST_RESERVE (200), TRAINER (gpu), PRECISION
# (32-true: the 16-mixed test once handed float16 leaves to the test-time fit, docs/results/2026-11-26_h200/
# table2_attempt), EXPERIMENT (table2_large), SYNTH_WORLDS (30), SYNTH_FRAMES (frames per sequence, 20),
# SYNTH_VARIATIONS ("clone,sunset,fog,rain"), SYNTH_WORKERS (16), TABLE2_EXTRA (more overrides for every run, e.g. a
# tiny budget to check this script on a CPU), WORK (scratch directory, /tmp/table2_gpu).
set -u
OUT=${1:?usage: bash benchmarks/table2_gpu.sh OUT_DIR}
PY=${PYTHON:-python3}
MAX_TIME=${MAX_TIME:-00:00:06:00}
TRAINER=${TRAINER:-gpu}
PRECISION=${PRECISION:-32-true}
EXPERIMENT=${EXPERIMENT:-table2_large}
WORK=${WORK:-/tmp/table2_gpu}
DATA=$WORK/synth
RUNS=$WORK/runs
export PYTHONUNBUFFERED=1 OMP_NUM_THREADS=1
mkdir -p "$OUT" "$RUNS"
start=$SECONDS
$PY "$(dirname "$0")/device_info.py" > "$OUT/device.txt" 2>&1

worlds='"0001","0002","0006","0018","0020"'
for ((i = 1; i <= ${SYNTH_WORLDS:-30} - 5; i++)); do worlds+=$(printf ',"%04d"' $((100 + i))); done
$PY -m sdn3d.cli.synth output_dir="$DATA" frames_per_sequence="${SYNTH_FRAMES:-20}" "worlds=[$worlds]" \
    "variations=[${SYNTH_VARIATIONS:-clone,sunset,fog,rain}]" edit_pairs=0 occluder_pairs=0 \
    workers="${SYNTH_WORKERS:-16}" overwrite=true > "$WORK/synth.log" 2>&1 \
  || { echo "synth failed"; tail -20 "$WORK/synth.log" | tee -a "$OUT/timing.txt"; exit 1; }
frames=$(find "$DATA/vkitti_1.3.1_rgb" -name '*.png' | wc -l)
echo "synth: $((SECONDS - start)) s, $frames frames, worlds [$worlds]" | tee "$OUT/timing.txt"
if [ -n "${DEADLINE:-}" ]; then  # each fit gets what is left after the tree and the tests' reserve
  fit_s=$((DEADLINE - (SECONDS - start) - ${TEST_RESERVE:-200}))
  if [ "$fit_s" -le 60 ]; then
    echo "DEADLINE=$DEADLINE leaves ${fit_s} s to fit: too little" | tee -a "$OUT/timing.txt"
    exit 1
  fi
  MAX_TIME=$(printf '00:%02d:%02d:%02d' $((fit_s / 3600)) $((fit_s % 3600 / 60)) $((fit_s % 60)))
  echo "fit budget: trainer.max_time=$MAX_TIME" | tee -a "$OUT/timing.txt"
fi

finish() {  # what the runs have, also when stopped: summaries, logs, per-epoch lines, the table of finished runs
  trap '' TERM INT  # `timeout` signals the script and then its whole process group: the second must not cut this
  echo "runs: $((SECONDS - start)) s${1:+ ($1)}" | tee -a "$OUT/timing.txt"
  [ -f "$RUNS/summary.jsonl" ] && cp "$RUNS/summary.jsonl" "$OUT/runs.jsonl"
  for log in "$RUNS"/*.log; do
    echo "== $(basename "$log")"
    grep -E "Error|error|Traceback|run finished|max_time|stopped" "$log" | tail -5
    tail -2 "$log"
  done > "$OUT/logs.txt" 2>&1
  for dir in "$RUNS"/*/; do
    echo "== $(basename "$dir")"
    grep -E "epoch [0-9]+/[0-9]+ done|Restoring states" "$dir/train.log"
  done > "$OUT/epochs.txt" 2>&1
  if [ -s "$RUNS/summary.jsonl" ]; then
    $PY -m sdn3d.cli.table2 --summary "$RUNS/summary.jsonl" --experiment "$EXPERIMENT" --out "$OUT" > /dev/null
  fi
  echo "table: $((SECONDS - start)) s" | tee -a "$OUT/timing.txt"
}
# Lightning's own SIGTERM handling lets a run go on: the runs still going are killed outright (their checkpoints are
# written atomically; `resume=` continues them), then what there is is written.
trap 'trap "" TERM INT; kill -KILL $(jobs -p) 2>/dev/null; wait 2>/dev/null; finish "stopped: the runs still going were killed"
      exit 143' TERM INT

run() {  # run NAME ABLATION SEED [OVERRIDE ...]
  local name=$1 ablation=$2 seed=$3
  shift 3
  # shellcheck disable=SC2086  # TABLE2_EXTRA is a list of overrides
  $PY -m sdn3d.cli.train branch=geometric experiment="$EXPERIMENT" data.root="$DATA" ablation="$ablation" \
      seed="$seed" trainer="$TRAINER" trainer.precision="$PRECISION" threads=1 trainer.max_time="$MAX_TIME" \
      trainer.enable_progress_bar=false summary_file="$RUNS/summary.jsonl" hydra.run.dir="$RUNS/$name" "$@" \
      ${TABLE2_EXTRA:-} > "$RUNS/$name.log" 2>&1 &
}
for seed in 0 1 2; do
  run "full_s$seed" full "$seed"
  run "no_reproj_s$seed" no_reproj "$seed"
done
run full_multibin_s0 full_multibin 0
if [ "${SET:-core}" = all ]; then
  run full_multibin_s1 full_multibin 1
  run full_multibin_s2 full_multibin 2
  for ablation in deep3dbox full_quaternion no_tau single_cad; do
    run "${ablation}_s0" "$ablation" 0
  done
fi
wait
finish
