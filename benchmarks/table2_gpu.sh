#!/usr/bin/env bash
# Table 2 in one go on a machine with one GPU (issue 29): the synthetic data of the Table 2 protocol, every run
# side by side on the one GPU (one CPU thread each), then sdn3d-table2.
#
#   bash benchmarks/table2_gpu.sh OUT_DIR
#
# Runs (experiment=table2: 64-px crops, batch 32, 40 L_pred + 20 joint epochs; each capped at $MAX_TIME):
#   seeds 0 1 2: full, no_reproj, and full as it was before issue 29 (variant=before: soft silhouette,
#                moving-average REINFORCE baseline with 4 samples)
#   seed 0:      deep3dbox, full_quaternion, no_tau, single_cad, and each issue-29 change reverted on its own
#                (variant=soft_silhouette, variant=moving_average)
# SET=core runs 10 of them: full and no_reproj at seeds 0 1 2, before, full_quaternion, no_tau, single_cad at seed 0.
# OUT_DIR gets: runs.jsonl (every run's summary), table2.md / table2.json, logs.txt (the end of each run's log),
# device.txt, timing.txt. Environment: PYTHON (python3), MAX_TIME (each run's trainer.max_time, 00:00:06:30),
# SYNTH_FRAMES (frames per sequence, 20), SYNTH_WORKERS (16), TRAINER (gpu), TABLE2_EXTRA (more overrides for
# every run, e.g. a tiny budget to check this script on a CPU), WORK (scratch directory, /tmp/table2_gpu).
set -u
OUT=${1:?usage: bash benchmarks/table2_gpu.sh OUT_DIR}
PY=${PYTHON:-python3}
MAX_TIME=${MAX_TIME:-00:00:06:30}
TRAINER=${TRAINER:-gpu}
WORK=${WORK:-/tmp/table2_gpu}
DATA=$WORK/synth
RUNS=$WORK/runs
export PYTHONUNBUFFERED=1 OMP_NUM_THREADS=1
mkdir -p "$OUT" "$RUNS"
start=$SECONDS
$PY "$(dirname "$0")/device_info.py" > "$OUT/device.txt" 2>&1
$PY -m sdn3d.cli.synth output_dir="$DATA" frames_per_sequence="${SYNTH_FRAMES:-20}" workers="${SYNTH_WORKERS:-16}" \
    overwrite=true > "$WORK/synth.log" 2>&1 || { echo "synth failed"; tail -20 "$WORK/synth.log"; exit 1; }
echo "synth: $((SECONDS - start)) s" | tee "$OUT/timing.txt"

run() {  # run NAME ABLATION VARIANT SEED [OVERRIDE ...]
  local name=$1 ablation=$2 variant=$3 seed=$4
  shift 4
  # shellcheck disable=SC2086  # TABLE2_EXTRA is a list of overrides
  $PY -m sdn3d.cli.train branch=geometric experiment=table2 data.root="$DATA" ablation="$ablation" seed="$seed" \
      trainer="$TRAINER" threads=1 trainer.max_time="$MAX_TIME" trainer.enable_progress_bar=false \
      summary_file="$RUNS/summary.jsonl" hydra.run.dir="$RUNS/$name" ${variant:+variant=$variant} "$@" \
      ${TABLE2_EXTRA:-} > "$RUNS/$name.log" 2>&1 &
}
BEFORE=(model.reproj_silhouette=soft model.baseline=moving_average)
if [ "${SET:-all}" = core ]; then  # what fits a shorter lease: 10 runs
  for seed in 0 1 2; do
    run "full_s$seed" full "" "$seed"
    run "no_reproj_s$seed" no_reproj "" "$seed"
  done
  run before_s0 full before 0 "${BEFORE[@]}"
  for ablation in full_quaternion no_tau single_cad; do
    run "${ablation}_s0" "$ablation" "" 0
  done
else
  for seed in 0 1 2; do
    run "full_s$seed" full "" "$seed"
    run "no_reproj_s$seed" no_reproj "" "$seed"
    run "before_s$seed" full before "$seed" "${BEFORE[@]}"
  done
  for ablation in deep3dbox full_quaternion no_tau single_cad; do
    run "${ablation}_s0" "$ablation" "" 0
  done
  run soft_silhouette_s0 full soft_silhouette 0 model.reproj_silhouette=soft
  run moving_average_s0 full moving_average 0 model.baseline=moving_average
fi
wait
echo "runs: $((SECONDS - start)) s" | tee -a "$OUT/timing.txt"
cp "$RUNS/summary.jsonl" "$OUT/runs.jsonl"
for log in "$RUNS"/*.log; do
  echo "== $(basename "$log")"
  grep -E "Error|error|Traceback|run finished|max_time" "$log" | tail -5
  tail -2 "$log"
done > "$OUT/logs.txt" 2>&1
$PY -m sdn3d.cli.table2 --summary "$RUNS/summary.jsonl" --out "$OUT" > /dev/null
echo "table: $((SECONDS - start)) s" | tee -a "$OUT/timing.txt"
