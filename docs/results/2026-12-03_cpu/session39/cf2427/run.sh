#!/bin/bash
# Session 39 cf2427: generate held-out tree 2427 once (main's code), then the four benchmark runs of PLAN.md,
# two at a time, one thread each. Code trees: git archive 6c4cf46 -> $S/issue_time, git archive 3a25892a -> $S/main_code.
S=/tmp/s39cf; T=$S/t2427; R=/tmp/w39/outputs/demo/runs; HERE=$(cd "$(dirname "$0")" && pwd)
PY=/work/main/.venv/bin/python
log() { echo "$* $(date -u +%T)" >> $S/log.txt; }
bench() {  # bench CODE OUT [overrides]
  local code=$1 out=$2; shift 2
  (cd $code && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 nice -n 5 $PY -m sdn3d.cli.bench counterfactual=true \
     data.root=$T run=$R threads=1 output_dir=$out "$@" > $out.log 2>&1; log "bench $out rc=$?")
}
if [ ! -f $T/_SUCCESS ]; then
  [ -e $T ] && { echo "$T exists without _SUCCESS: not regenerating"; exit 1; }
  log "gen start"
  OMP_NUM_THREADS=1 PYTHONPATH=$S/main_code/src:$S/main_code nice -n 5 $PY $HERE/gen_cf.py $T 2427 \
    0001,0002,0006,0018,0020,0003,0004,0005,0007,0008,0009,0010 4 > $S/gen.log 2>&1
  log "gen rc=$?"
fi
FILLS='counterfactual_fills=[auto,telea,patchmatch,rays,learnt]'
bench $S/issue_time $S/issue_oracle 'counterfactual_sources=[oracle]' &
bench $S/main_code $S/main_oracle 'counterfactual_sources=[oracle]' "$FILLS" 'counterfactual_kinds=[turn,delete]' &
wait
bench $S/issue_time $S/issue_pred 'counterfactual_sources=[gt,semantic]' &
bench $S/main_code $S/main_pred 'counterfactual_sources=[gt,semantic]' "$FILLS" 'counterfactual_kinds=[turn,delete]' &
wait
log "all done"
