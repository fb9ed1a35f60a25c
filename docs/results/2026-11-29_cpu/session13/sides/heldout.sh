#!/bin/bash
# heldout.sh FINAL_COMMIT: held-out seed 2125, generated after the code was final and measured once: main (97b891e, the
# branch point, as git archive: BASE) against this branch's FINAL_COMMIT (git archive: NEW). The counterfactual tree
# is session 5's gen_cf.py recipe (worlds 0006,0018,0020, 6 cars, turns 15/45/90/180). sdn3d-bench
# counterfactual=true, turns only, photo fill rays, ground-truth geometry (oracle) and predicted proposals (semantic +
# geometric branches of the session 11 demo, the bench's default test-time fit); compare.py --bench for the tables.
set -u
D=/tmp/s13data/sides; H=$D/held; R=$(cd "$(dirname "$0")" && pwd); REPO=$(cd "$R/../../../../.." && pwd)
mkdir -p $H
BASE=$D/main; NEW=$D/final
rm -rf $NEW && mkdir -p $NEW && (cd $REPO && git archive "$1" | tar -x -C $NEW)
CK="checkpoints.semantic=/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s11data/demo/out/runs/geometric/checkpoints/inference.pt"
PY="nice -n 5 env OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
run() { S=$1; O=$2; shift 2
  (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$H/cf2125 output_dir=$O examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_kinds=[turn]' "$@" > $O.log 2>&1; echo "$O rc=$? $(date -u +%T)" >> $H/held.log)
}
echo "start $(date -u +%T) final=$1" >> $H/held.log
[ -e $H/cf2125/_SUCCESS ] || PYTHONPATH=$NEW/src $PY $REPO/docs/results/2026-11-28_cpu/session5/turns/gen_cf.py $H/cf2125 2125 0006,0018,0020 6 > $H/gen_cf2125.log 2>&1
for C in new:$NEW base:$BASE; do run ${C#*:} $H/turns_oracle_${C%%:*} 'counterfactual_sources=[oracle]'; done
PYTHONPATH=$NEW/src $PY $R/compare.py --bench $H/turns_oracle_new/counterfactual.json $H/turns_oracle_base/counterfactual.json > $R/heldout2125_turns_oracle.md
for C in new:$NEW base:$BASE; do run ${C#*:} $H/turns_pred_${C%%:*} 'counterfactual_sources=[semantic]' $CK; done
PYTHONPATH=$NEW/src $PY $R/compare.py --bench $H/turns_pred_new/counterfactual.json $H/turns_pred_base/counterfactual.json > $R/heldout2125_turns_predicted.md
echo "done $(date -u +%T)" >> $H/held.log
