#!/bin/bash
# heldout.sh NEW_COMMIT: held-out seed 2131, generated after the code was final and measured once: main (d56e075, the
# branch point, as git archive: BASE) against this branch (NEW_COMMIT, as git archive: NEW). The counterfactual tree is
# session 5's gen_cf.py recipe (worlds 0006,0018,0020, clone + fog, 6 cars). sdn3d-bench counterfactual=true, deletes:
# ground-truth geometry (oracle) with main's telea, patchmatch, rays, learnt and the generator (the session 11 demo's
# textural branch) and the branch's rays and learnt; predicted proposals (the demo's semantic + geometric branches)
# with rays and learnt on both. Tables by session 12's paired.py and fills.py; the real frame's strip (session 4's
# real_strip.py) from both trees.
set -u
D=/tmp/s14data/roadfill; H=$D/held; R=$(cd "$(dirname "$0")" && pwd); WT=$(cd "$R/../../../../.." && pwd)
BASE=$D/base; NEW=$D/final
mkdir -p $H $NEW
git -C "$WT" archive "$1" | tar -x -C $NEW
PY="nice -n 5 env OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
(cd $NEW && PYTHONPATH=$NEW/src $PY docs/results/2026-11-28_cpu/session5/turns/gen_cf.py $H/cf2131 2131 0006,0018,0020 6 > $H/gen2131.log 2>&1)
TX=checkpoints.textural=/tmp/s11data/demo/out/runs/textural/checkpoints/inference.pt
$R/bench.sh $NEW $H/cf2131 $H/oracle_new oracle '[rays,learnt]'
$R/bench.sh $BASE $H/cf2131 $H/oracle_base oracle '[telea,patchmatch,rays,learnt,generator]' $TX
$R/bench.sh $NEW $H/cf2131 $H/pred_new semantic '[rays,learnt]'
$R/bench.sh $BASE $H/cf2131 $H/pred_base semantic '[rays,learnt]'
P=$WT/docs/results/2026-11-29_cpu/session12/realframe/paired.py
for S in oracle pred; do
  for M in photo:rays photo:learnt; do
    PYTHONPATH=$NEW/src $PY $P $H/${S}_new/counterfactual.json $H/${S}_base/counterfactual.json $M
  done > $R/heldout2131_${S}_branch_vs_main.md
  PYTHONPATH=$NEW/src $PY $R/fills.py $H/${S}_new/counterfactual.json $H/${S}_base/counterfactual.json > $R/heldout2131_${S}_fills.md
done
(cd $BASE && PYTHONPATH=$BASE/src $PY docs/results/2026-11-28_cpu/session4/poses/real_strip.py /tmp/s11data/demo/out/runs $H/strip_base > $H/strip_base.log 2>&1)
(cd $NEW && PYTHONPATH=$NEW/src $PY docs/results/2026-11-28_cpu/session4/poses/real_strip.py /tmp/s11data/demo/out/runs $H/strip_new > $H/strip_new.log 2>&1)
echo done
