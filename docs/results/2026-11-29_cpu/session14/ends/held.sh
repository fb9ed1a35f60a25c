#!/bin/bash
# held.sh FINAL_COMMIT: the held-out seeds, generated after the code was final and measured once: counterfactual tree
# cf2127 (session 5's gen_cf.py recipe, as cf33) and Table 1 tree t1_2129 (session 9's gen_t1.py). Main (d56e075, the
# branch point) against FINAL_COMMIT, both as git archives. Counterfactual: sdn3d-bench counterfactual=true, turns only,
# photo fill rays, ground-truth geometry (oracle) and predicted (the session 11 demo's branches); Table 1: photo row
# at 312x96 with fit_proposals, ground-truth masks (oracle) and semantic proposals (session 11 semrain's dbench.py, the
# de-renders cached per tree: main's run fills the cache, the branch's reads it; they do not depend on the part labels).
set -u
D=/tmp/s14data/ends; H=$D/held; R=$(cd "$(dirname "$0")" && pwd); REPO=$(cd "$R/../../../../.." && pwd)
mkdir -p $H
NEW=$D/final; BASE=$D/main
rm -rf $NEW && mkdir -p $NEW && (cd $REPO && git archive "$1" | tar -x -C $NEW)
PY="nice -n 5 env OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
echo "start $(date -u +%T) final=$1" >> $H/held.log
[ -e $H/cf2127/_SUCCESS ] || PYTHONPATH=$NEW/src $PY $REPO/docs/results/2026-11-28_cpu/session5/turns/gen_cf.py $H/cf2127 2127 0006,0018,0020 6 > $H/gen_cf2127.log 2>&1
[ -e $H/t1_2129/_SUCCESS ] || PYTHONPATH=$NEW/src $PY $REPO/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $H/t1_2129 2129 > $H/gen_t1_2129.log 2>&1
echo "generated $(date -u +%T)" >> $H/held.log
CK="checkpoints.semantic=/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s11data/demo/out/runs/geometric/checkpoints/inference.pt"
DB=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SRC in oracle semantic; do
  for C in base:$BASE new:$NEW; do S=${C#*:}; N=${C%%:*}; EXTRA=""; [ $SRC = semantic ] && EXTRA=$CK
    (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$H/cf2127 output_dir=$H/cf_${SRC}_$N examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_kinds=[turn]' "counterfactual_sources=[$SRC]" $EXTRA > $H/cf_${SRC}_$N.log 2>&1)
    echo "cf $SRC $N rc=$? $(date -u +%T)" >> $H/held.log
  done
done
for P in gt semantic; do
  for C in base:$BASE new:$NEW; do S=${C#*:}; N=${C%%:*}
    (cd $S && PYTHONPATH=$S/src:$S OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DB $H/cache2129 $H/t1_${P}_$N.dump data.root=$H/t1_2129 'data.image_size=[312,96]' run=/tmp/s11data/demo/out 'compose=[photo]' "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$H/t1_${P}_$N > $H/t1_${P}_$N.log 2>&1)
    echo "t1 $P $N rc=$? $(date -u +%T)" >> $H/held.log
  done
done
PYTHONPATH=$NEW/src $PY $R/pooled.py $H/cf_oracle_new/counterfactual.json:$H/cf_oracle_base/counterfactual.json > $R/heldout2127_turns_oracle.md
PYTHONPATH=$NEW/src $PY $R/pooled.py $H/cf_semantic_new/counterfactual.json:$H/cf_semantic_base/counterfactual.json > $R/heldout2127_turns_predicted.md
$PY $REPO/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py "Table 1 held-out 2129, ground-truth masks (oracle): branch (new) vs main (base)" $H/t1_gt_base:$H/t1_gt_new > $R/heldout2129_table1_gt.txt
$PY $REPO/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py "Table 1 held-out 2129, semantic proposals: branch (new) vs main (base)" $H/t1_semantic_base:$H/t1_semantic_new > $R/heldout2129_table1_semantic.txt
echo "done $(date -u +%T)" >> $H/held.log
