#!/bin/bash
# heldout.sh: held-out seed 2119, generated after the code was final (ff013f1) and measured once, main (01655bc, the
# branch point, as git archive: BASE) against this branch (ff013f1: NEW). The counterfactual tree is session 5's
# gen_cf.py recipe (worlds 0006,0018,0020, 6 cars); the recolour tree session 10's gen_recolor2111.py with seed 2119.
# sdn3d-bench counterfactual=true, photo fill rays, ground-truth geometry (oracle) without checkpoints, and the
# predicted proposals (semantic + geometric branches of the session 11 demo); paired.py for the tables.
D=/tmp/s12data/realframe; H=$D/held; R=$(cd "$(dirname "$0")" && pwd)
BASE=$D/base; NEW=$D/c5
CK="checkpoints.semantic=/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s11data/demo/out/runs/geometric/checkpoints/inference.pt"
run() { S=$1; T=$2; O=$3; shift 3
  (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$T output_dir=$O examples=0 threads=1 'counterfactual_fills=[rays]' "$@" > $O.log 2>&1; echo "$O rc=$?" >> $H/held.log)
}
PY="nice -n 5 env OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
while [ ! -e $H/cf2119/_SUCCESS ]; do sleep 15; done
for C in new:$NEW base:$BASE; do run ${C#*:} $H/cf2119 $H/turns_oracle_${C%%:*} 'counterfactual_kinds=[turn]' 'counterfactual_sources=[oracle]'; done
for C in new:$NEW base:$BASE; do run ${C#*:} $H/cf2119 $H/deletes_oracle_${C%%:*} 'counterfactual_kinds=[delete]' 'counterfactual_sources=[oracle]'; done
PYTHONPATH=$NEW/src $PY $R/paired.py $H/turns_oracle_new/counterfactual.json $H/turns_oracle_base/counterfactual.json > $R/heldout2119_turns_oracle.md
PYTHONPATH=$NEW/src $PY $R/paired.py $H/deletes_oracle_new/counterfactual.json $H/deletes_oracle_base/counterfactual.json > $R/heldout2119_deletes_oracle.md
PYTHONPATH=$NEW/src $PY $R/gen_recolor2119.py > $H/gen_rc2119.log 2>&1
for C in new:$NEW base:$BASE; do run ${C#*:} $H/cf2119 $H/turns_pred_${C%%:*} 'counterfactual_kinds=[turn]' 'counterfactual_sources=[semantic]' $CK; done
PYTHONPATH=$NEW/src $PY $R/paired.py $H/turns_pred_new/counterfactual.json $H/turns_pred_base/counterfactual.json > $R/heldout2119_turns_predicted.md
for C in new:$NEW base:$BASE; do PYTHONPATH=${C#*:}/src $PY $R/../../session10/lead/recolor_eval.py $H/rc2119 $H/rc2119_${C%%:*}.json 90 > $H/rc2119_${C%%:*}.txt 2>&1; done
echo done >> $H/held.log
