#!/usr/bin/env bash
# Issue 28: which semantic-branch recipe buys the demo the most proposal recall per training step, measured for
# many recipes side by side on one GPU machine (one CPU thread each), each with benchmarks/recall_budget.py.
#
#   bash benchmarks/recall_budget_gpu.sh OUT_DIR
#
# Data (sdn3d-synth, the demo's settings, conf/demo.yaml): d16 = the demo's own tree (16 frames per sequence, 20
# training frames), d64 and d128 (64 / 128 frames per sequence). Every run is scored on the *training* part of a
# tree of another seed (seed 1, 64 frames per sequence): frames no run trained on, and not any tree's test part.
# The step axis carries over to the CPU; the seconds do not (the CPU's seconds per step are measured there).
# SET=explore (default): twelve recipes at one seed, 600 steps; SET=demo: the candidates it left (slim DRN, skip
# decoder, AdamW 4e-3; 128 or 256 frames per sequence) at 300 and 400 steps, 2-3 seeds each; SET=confirm: the
# chosen recipe (ENet weights, colour jitter) and the same without them at seeds 2 and 3.
# OUT_DIR gets sweep.json (every run's recall.json of recall_budget.py, by name), logs.txt (the end of each run's
# log), device.txt and timing.txt. Environment: PYTHON (python3), STEPS (600), EVERY (50), DEVICE (cuda),
# MAX_TIME (each run's trainer.max_time, 00:00:04:00: a lease ends), WORK (/tmp/recall_budget).
set -u
OUT=${1:?usage: bash benchmarks/recall_budget_gpu.sh OUT_DIR}
PY=${PYTHON:-python3}
STEPS=${STEPS:-600}
EVERY=${EVERY:-50}
DEVICE=${DEVICE:-cuda}
MAX_TIME=${MAX_TIME:-00:00:04:00}
WORK=${WORK:-/tmp/recall_budget}
export PYTHONUNBUFFERED=1 OMP_NUM_THREADS=1
mkdir -p "$OUT" "$WORK/runs"
start=$SECONDS
$PY "$(dirname "$0")/device_info.py" > "$OUT/device.txt" 2>&1
synth() {  # synth NAME FRAMES SEED EDIT_PAIRS
  $PY -m sdn3d.cli.synth output_dir="$WORK/$1" frames_per_sequence="$2" seed="$3" edit_pairs="$4" \
      'worlds=["0001","0002"]' 'variations=[clone]' image_size=[624,192] cars_per_frame=[5,10] \
      max_edit_operations=3 workers=8 overwrite=true > "$WORK/$1.log" 2>&1 || { echo "synth $1 failed"; tail "$WORK/$1.log"; }
}
if [ "${SET:-explore}" = explore ]; then
  synth d16 16 0 4 & synth d64 64 0 4 & synth d128 128 0 4 & synth eval 64 1 0 &
elif [ "${SET}" = confirm ]; then
  synth d128 128 0 4 & synth eval 64 1 0 &
else
  synth d128 128 0 4 & synth d256 256 0 4 & synth eval 64 1 0 &
fi
wait
echo "synth: $((SECONDS - start)) s" | tee "$OUT/timing.txt"

SLIM2=('model.channels=[16,16,32,64,64,128,128,128]' model.decoder=skip model.head_channels=64 model.optimizer=adamw)
CPU_NET=('model.channels=[16,32,64,128,128,256,256,256]' model.optimizer=adamw)
run() {  # run NAME DATA STEPS [OVERRIDE ...]
  local name=$1 data=$2 steps=$3
  shift 3
  $PY benchmarks/recall_budget.py --data-root "$WORK/$data" --eval-root "$WORK/eval" --part train \
      --out "$WORK/runs/$name" --steps "$steps" --every "$EVERY" --threads 1 --device "$DEVICE" -- \
      trainer.precision=32-true trainer.enable_progress_bar=false trainer.max_time="$MAX_TIME" "$@" \
      > "$WORK/runs/$name.log" 2>&1 || { echo "$name failed"; tail -5 "$WORK/runs/$name.out"; }
}
if [ "${SET:-explore}" = explore ]; then  # first look: one seed each, 600 steps
  run slim2_d64 d64 "$STEPS" "${SLIM2[@]}" model.lr=0.002 &
  run slim2_d64_seed1 d64 "$STEPS" "${SLIM2[@]}" model.lr=0.002 seed=1 &
  run slim2_d64_lr4 d64 "$STEPS" "${SLIM2[@]}" model.lr=0.004 &
  run slim2_d16 d16 "$STEPS" "${SLIM2[@]}" model.lr=0.002 &
  run slim2_d128 d128 "$STEPS" "${SLIM2[@]}" model.lr=0.002 &
  run slim2_d64_b4 d64 "$STEPS" "${SLIM2[@]}" model.lr=0.002 datamodule.batch_size=4 &
  run slim2_d64_enet_jitter d64 "$STEPS" "${SLIM2[@]}" model.lr=0.002 model.class_weighting=enet model.color_jitter=0.2 &
  run slim3_d64 d64 "$STEPS" 'model.channels=[8,16,32,64,64,128,128,128]' model.decoder=skip model.head_channels=64 \
      'model.decoder_channels=[32,16,16]' model.optimizer=adamw model.lr=0.002 &
  run cpunet_skip_d64 d64 "$STEPS" "${CPU_NET[@]}" model.decoder=skip model.lr=0.002 &
  run cpunet_bilinear_d64 d64 "$STEPS" "${CPU_NET[@]}" model.decoder=bilinear model.lr=0.002 &
  run demo_short_d64 d64 "$STEPS" &
  run slim2_d64_sigma2 d64 "$STEPS" "${SLIM2[@]}" model.lr=0.002 model.center_sigma=2.0 &
elif [ "${SET}" = confirm ]; then  # SET=confirm: the chosen recipe and its plain twin at two more seeds
  for seed in 2 3; do
    run "d128_lr4_enet_jitter_s$seed" d128 400 "${SLIM2[@]}" model.lr=0.004 model.class_weighting=enet \
        model.color_jitter=0.2 seed="$seed" &
    run "d128_lr4_s$seed" d128 400 "${SLIM2[@]}" model.lr=0.004 seed="$seed" &
  done
else  # SET=demo: the candidates the first look left, at the demo's own schedule length, several seeds
  for seed in 0 1 2; do
    run "d128_lr4_s$seed" d128 400 "${SLIM2[@]}" model.lr=0.004 seed="$seed" &
  done
  for seed in 0 1; do
    run "d256_lr4_s$seed" d256 400 "${SLIM2[@]}" model.lr=0.004 seed="$seed" &
    run "d128_lr4_enet_jitter_s$seed" d128 400 "${SLIM2[@]}" model.lr=0.004 model.class_weighting=enet \
        model.color_jitter=0.2 seed="$seed" &
    run "d128_lr6_s$seed" d128 400 "${SLIM2[@]}" model.lr=0.006 seed="$seed" &
    run "d128_lr4_300steps_s$seed" d128 300 "${SLIM2[@]}" model.lr=0.004 seed="$seed" &
  done
fi
wait
echo "all: $((SECONDS - start)) s" | tee -a "$OUT/timing.txt"
$PY - "$WORK/runs" "$OUT/sweep.json" <<'PY'
import json, pathlib, sys
runs = pathlib.Path(sys.argv[1])
sweep = {p.parent.name: json.loads(p.read_text()) for p in sorted(runs.glob("*/recall.json"))}
pathlib.Path(sys.argv[2]).write_text(json.dumps(sweep, indent=1))
for name, r in sweep.items():
    best = max(r["rows"], key=lambda row: row["recall"], default=None)
    print(name, "last:", r["rows"][-1] if r["rows"] else None, "best recall:", best)
PY
for f in "$WORK"/runs/*.out; do echo "== $f"; tail -3 "$f"; done > "$OUT/logs.txt" 2>&1
