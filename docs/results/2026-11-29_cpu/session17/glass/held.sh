#!/bin/bash
# held.sh FINAL_COMMIT: the held-out seeds of this helper, generated after the code was final and measured once.
# Counterfactual tree cf2153 (session 5's gen_cf.py, cf33's recipe: scenes 0006,0018,0020, 6 frames) and Table 1 tree
# t1_2155 (session 9's gen_t1.py). Main (35b8cdf, /tmp/s17data/lead/base_35b) against FINAL_COMMIT (a git archive):
# sdn3d-bench counterfactual=true (turns, photo fill rays; ground-truth geometry (oracle) and predicted: the session 11
# demo's branches), Table 1 photo row at 312x96 (ground-truth masks (oracle) and semantic proposals; session 11
# semrain's dbench.py: main's run fills the de-render cache, the branch's reads it). Tables: session 14's pooled.py,
# session 13's paired.py.
set -u
FINAL=$1; CF=2153; T1=2155
HERE=$(cd "$(dirname "$0")" && pwd); REPO=$(cd "$HERE/../../../../.." && pwd); RES=$REPO/docs/results
H=/tmp/s17data/glass/held; MAIN=/tmp/s17data/lead/base_35b; NEW=$H/final
mkdir -p $H && rm -rf $NEW && mkdir -p $NEW && (cd "$REPO" && git archive "$FINAL" | tar -x -C $NEW)
PY="nice -n 5 env OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
log() { echo "$* $(date -u +%T)" >> $H/held.log; }
log "start final=$FINAL"
[ -e $H/cf$CF/_SUCCESS ] || PYTHONPATH=$NEW/src $PY $RES/2026-11-28_cpu/session5/turns/gen_cf.py $H/cf$CF $CF \
  0006,0018,0020 6 > $H/gen_cf$CF.log 2>&1
[ -e $H/t1_$T1/_SUCCESS ] || PYTHONPATH=$NEW/src $PY $RES/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py \
  $H/t1_$T1 $T1 > $H/gen_t1_$T1.log 2>&1
log generated
RUNS=/tmp/s11data/demo/out/runs
CK="checkpoints.semantic=$RUNS/semantic/checkpoints/inference.pt checkpoints.geometric=$RUNS/geometric/checkpoints/inference.pt"
for SRC in oracle semantic; do
  for C in main:$MAIN new:$NEW; do
    S=${C#*:}; N=${C%%:*}; EXTRA=""; [ $SRC = semantic ] && EXTRA=$CK
    # shellcheck disable=SC2086
    (cd $S && PYTHONPATH=$S/src $PY -m sdn3d.cli.bench counterfactual=true data.root=$H/cf$CF \
      output_dir=$H/cf_${SRC}_$N examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_kinds=[turn]' \
      "counterfactual_sources=[$SRC]" $EXTRA > $H/cf_${SRC}_$N.log 2>&1)
    log "cf $SRC $N rc=$?"
  done
done
DBENCH=$RES/2026-11-29_cpu/session11/semrain/scripts/dbench.py
for P in gt semantic; do
  for C in main:$MAIN new:$NEW; do
    S=${C#*:}; N=${C%%:*}
    (cd $S && PYTHONPATH=$S/src:$S $PY $DBENCH $H/cache$T1 $H/t1_${P}_$N.dump data.root=$H/t1_$T1 \
      'data.image_size=[312,96]' run=/tmp/s11data/demo/out 'compose=[photo]' "proposals=[$P]" scene=derender \
      threads=1 examples=0 output_dir=$H/t1_${P}_$N > $H/t1_${P}_$N.log 2>&1)
    log "t1 $P $N rc=$?"
  done
done
POOLED=$RES/2026-11-29_cpu/session14/ends/pooled.py; PAIRED=$RES/2026-11-29_cpu/session13/rotloss/scripts/paired.py
for SRC in oracle:oracle semantic:predicted; do
  PYTHONPATH=$NEW/src $PY $POOLED $H/cf_${SRC%%:*}_new/counterfactual.json:$H/cf_${SRC%%:*}_main/counterfactual.json \
    > $HERE/heldout${CF}_turns_${SRC#*:}.md
done
$PY $PAIRED "Table 1 held-out $T1, ground-truth masks (oracle): branch (new) vs main (base)" \
  $H/t1_gt_main:$H/t1_gt_new > $HERE/heldout${T1}_table1_gt.txt
$PY $PAIRED "Table 1 held-out $T1, semantic proposals: branch (new) vs main (base)" \
  $H/t1_semantic_main:$H/t1_semantic_new > $HERE/heldout${T1}_table1_semantic.txt
log done
