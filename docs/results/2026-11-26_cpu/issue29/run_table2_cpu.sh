#!/usr/bin/env bash
# Table 2 on this 2-core CPU (issue 29), two runs at a time, one thread each. Runs of one seed share stage 1 (40
# L_pred epochs: identical for full, w/o L_reproj and the before-issue-29 model, whose differences start in the
# joint stage), so stage 1 runs once per seed and each arm continues from its last checkpoint (ckpt_path=) for the
# 20 joint epochs. The other rows train from scratch (their networks or targets differ from the first step).
#   bash docs/results/2026-11-26_cpu/issue29/run_table2_cpu.sh       (data: sdn3d-synth output_dir=$DATA
#                                                                      frames_per_sequence=20, the default vehicles)
set -u
DATA=${DATA:-/work/runs/synth20h}
W=${W:-/work/runs/t2cpu}
TRAIN="sdn3d-train branch=geometric experiment=table2 data.root=$DATA threads=1 trainer.enable_progress_bar=false"
export OMP_NUM_THREADS=1
mkdir -p "$W"
stage1() {  # the shared stage 1 of seed $1
  [ -f "$W/stage1_s$1/checkpoints/last.ckpt" ] && grep -q "stage1_s$1\"" "$W/stage1.jsonl" 2>/dev/null && return
  $TRAIN ablation=full seed="$1" trainer.max_epochs=40 test_after_fit=false summary_file="$W/stage1.jsonl" \
      hydra.run.dir="$W/stage1_s$1" > "$W/stage1_s$1.log" 2>&1
}
fork() {  # fork SEED NAME ABLATION [OVERRIDE ...]: the joint stage from seed SEED's stage 1
  local seed=$1 name=$2 ablation=$3
  shift 3
  until grep -q "stage1_s$seed\"" "$W/stage1.jsonl" 2>/dev/null; do sleep 20; done
  $TRAIN ablation="$ablation" seed="$seed" ckpt_path="$W/stage1_s$seed/checkpoints/last.ckpt" \
      summary_file="$W/summary.jsonl" hydra.run.dir="$W/${name}_s$seed" "$@" > "$W/${name}_s$seed.log" 2>&1
}
scratch() {  # scratch NAME ABLATION: a whole run of seed 0
  $TRAIN ablation="$2" seed=0 summary_file="$W/summary.jsonl" hydra.run.dir="$W/$1_s0" > "$W/$1_s0.log" 2>&1
}
export -f stage1 fork scratch
export W TRAIN
BEFORE="variant=before model.reproj_silhouette=soft model.baseline=moving_average"
printf '%s\n' \
  "fork 0 full full" "fork 0 no_reproj no_reproj" "fork 1 full full" "fork 1 no_reproj no_reproj" \
  "stage1 2" "fork 0 before full $BEFORE" "fork 2 full full" "fork 2 no_reproj no_reproj" \
  "fork 1 before full $BEFORE" "fork 2 before full $BEFORE" \
  "scratch single_cad single_cad" "scratch full_quaternion full_quaternion" "scratch no_tau no_tau" \
  "scratch deep3dbox deep3dbox" \
  | xargs -P 2 -I{} bash -c "{}"
