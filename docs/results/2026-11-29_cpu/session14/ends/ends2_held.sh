#!/bin/bash
# ends2_held.sh FINAL_COMMIT CF_SEED T1_SEED: the follow-up's held-out seeds, generated after the code was final and
# measured once: counterfactual tree cf$CF_SEED (session 5's gen_cf.py, cf33's recipe: scenes 0006,0018,0020, 6 frames)
# and Table 1 tree t1_$T1_SEED (session 9's gen_t1.py). Main (d56e075, the branch point) against FINAL_COMMIT, both as
# git archives, with held.sh's commands (sdn3d-bench counterfactual=true, turns only, photo fill rays, ground-truth
# geometry (oracle) and predicted; Table 1 photo row at 312x96, ground-truth masks (oracle) and semantic proposals,
# session 11 semrain's dbench.py, main's run fills the de-render cache and the branch's reads it). Tables by pooled.py
# and session 13's paired.py into this folder (ends2_heldout*).
set -u
FINAL=$1; CF=$2; T1=$3
D=/tmp/s14data/ends2; H=$D/held; R=$(cd "$(dirname "$0")" && pwd); REPO=$(cd "$R/../../../../.." && pwd)
mkdir -p $H
NEW=$D/final; BASE=$D/main
for X in "$NEW:$FINAL" "$BASE:d56e075"; do rm -rf ${X%%:*} && mkdir -p ${X%%:*} && (cd $REPO && git archive "${X#*:}" | tar -x -C ${X%%:*}); done
PY="nice -n 5 env OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
echo "start $(date -u +%T) final=$FINAL" >> $H/held.log
[ -e $H/cf$CF/_SUCCESS ] || PYTHONPATH=$NEW/src $PY $REPO/docs/results/2026-11-28_cpu/session5/turns/gen_cf.py $H/cf$CF $CF 0006,0018,0020 6 > $H/gen_cf$CF.log 2>&1
[ -e $H/t1_$T1/_SUCCESS ] || PYTHONPATH=$NEW/src $PY $REPO/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $H/t1_$T1 $T1 > $H/gen_t1_$T1.log 2>&1
echo "generated $(date -u +%T)" >> $H/held.log
CK="checkpoints.semantic=/tmp/s11data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s11data/demo/out/runs/geometric/checkpoints/inference.pt"
DB=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for SRC in oracle semantic; do
  for C in base:$BASE new:$NEW; do S=${C#*:}; N=${C%%:*}; EXTRA=""; [ $SRC = semantic ] && EXTRA=$CK
    (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$H/cf$CF output_dir=$H/cf_${SRC}_$N examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_kinds=[turn]' "counterfactual_sources=[$SRC]" $EXTRA > $H/cf_${SRC}_$N.log 2>&1)
    echo "cf $SRC $N rc=$? $(date -u +%T)" >> $H/held.log
  done
done
for P in gt semantic; do
  for C in base:$BASE new:$NEW; do S=${C#*:}; N=${C%%:*}
    (cd $S && PYTHONPATH=$S/src:$S OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DB $H/cache$T1 $H/t1_${P}_$N.dump data.root=$H/t1_$T1 'data.image_size=[312,96]' run=/tmp/s11data/demo/out 'compose=[photo]' "proposals=[$P]" scene=derender threads=1 examples=0 output_dir=$H/t1_${P}_$N > $H/t1_${P}_$N.log 2>&1)
    echo "t1 $P $N rc=$? $(date -u +%T)" >> $H/held.log
  done
done
PYTHONPATH=$NEW/src $PY $R/pooled.py $H/cf_oracle_new/counterfactual.json:$H/cf_oracle_base/counterfactual.json > $R/ends2_heldout${CF}_turns_oracle.md
PYTHONPATH=$NEW/src $PY $R/pooled.py $H/cf_semantic_new/counterfactual.json:$H/cf_semantic_base/counterfactual.json > $R/ends2_heldout${CF}_turns_predicted.md
$PY $REPO/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py "Table 1 held-out $T1, ground-truth masks (oracle): branch (new) vs main (base)" $H/t1_gt_base:$H/t1_gt_new > $R/ends2_heldout${T1}_table1_gt.txt
$PY $REPO/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py "Table 1 held-out $T1, semantic proposals: branch (new) vs main (base)" $H/t1_semantic_base:$H/t1_semantic_new > $R/ends2_heldout${T1}_table1_semantic.txt
echo "done $(date -u +%T)" >> $H/held.log
