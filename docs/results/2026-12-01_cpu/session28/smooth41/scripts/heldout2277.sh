#!/bin/bash
# heldout2277.sh FINAL_COMMIT: the held-out tree (seed 2277, gen_cf.py's recipe: worlds 0006,0018,0020, 6 cars), generated
# once after the merge rule's commit, measured once: main 9da18f5b (/tmp/s28/smooth41/base) against FINAL_COMMIT (a
# git archive, its defaults), counterfactual turns (cf_turns.sh: fill rays, w28), ground-truth geometry (oracle) and
# predicted, two at a time; then paired.py into tables/heldout2277.md.
set -u
FINAL=$1; D=$(cd "$(dirname "$0")" && pwd); H=/tmp/s28/smooth41/held; O=$H/cf
mkdir -p $O && rm -rf $H/final && mkdir -p $H/final && (cd "$D" && git -C "$(git rev-parse --show-toplevel)" archive "$FINAL" | tar -x -C $H/final)
# (the first run archived from this folder, which gives this folder's files alone: $H/final had no src/, and the
# "branch" rows ran main's installed library; SKIP_MAIN=1 reruns the branch's rows alone on the same tree.)
[ -d $H/final/src/sdn3d ] || { echo "no src in $H/final" >&2; exit 1; }
echo "start $FINAL $(date -u +%T)" >> $H/held.log
[ -e $H/tree2277/_SUCCESS ] || (PYTHONPATH=/tmp/s28/smooth41/base/src OMP_NUM_THREADS=1 nice -n 5 \
  /work/main/.venv/bin/python $D/gen_cf.py $H/tree2277 2277 0006,0018,0020 6 > $H/gen2277.log 2>&1)
echo "generated $(date -u +%T)" >> $H/held.log
if [ -n "${SKIP_MAIN:-}" ]; then
  bash $D/cf_turns.sh $H/final $H/tree2277 $O/final_oracle oracle >> $H/held.log &
  bash $D/cf_turns.sh $H/final $H/tree2277 $O/final_semantic semantic >> $H/held.log
  wait
else
  for S in oracle semantic; do
    bash $D/cf_turns.sh /tmp/s28/smooth41/base $H/tree2277 $O/main_$S $S >> $H/held.log &
    bash $D/cf_turns.sh $H/final $H/tree2277 $O/final_$S $S >> $H/held.log
    wait
  done
fi
cd $O && PYTHONPATH=$H/final/src /work/main/.venv/bin/python $D/paired.py cf2277 main_oracle final_oracle > $D/../tables/heldout2277.md
PYTHONPATH=$H/final/src /work/main/.venv/bin/python $D/paired.py cf2277 main_semantic final_semantic | tail -n +3 >> $D/../tables/heldout2277.md
echo "done $(date -u +%T)" >> $H/held.log
