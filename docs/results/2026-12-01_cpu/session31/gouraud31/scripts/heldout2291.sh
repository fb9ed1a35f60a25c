#!/bin/bash
# heldout2291.sh MAIN_COMMIT BRANCH_COMMIT: the held-out tree (seed 2291, gen_cf.py's recipe with worlds
# 0001,0002,0006,0018,0020 and 8 cars, main's generator), generated once after the merge rule's commit, measured once:
# main MAIN_COMMIT (a plain tree, /tmp/s31/gouraud31/base) against BRANCH_COMMIT (a plain tree of the whole commit, its
# defaults), counterfactual turns (cf_turns.sh: fill rays, w31), ground-truth geometry (oracle) and predicted, ONE run
# at a time (the CPU is shared); then paired.py (car-clustered intervals, pairs beside), exact.py, percar.py,
# flatcheck.py into tables/. (session 30 gouraud30's heldout2283.sh, seed, paths, weights changed, runs one at a time.)
set -u
MAIN=$1; BR=$2; D=$(cd "$(dirname "$0")" && pwd); R=$(git -C "$D" rev-parse --show-toplevel); H=/tmp/s31/gouraud31; O=$H/cf
T=$D/../tables
[ -e /tmp/s31/demo_DONE ] || { echo "weights w31 not ready" >&2; exit 1; }
[ -e $H/tree2291 ] && { echo "tree2291 exists already: the held-out tree is generated once" >&2; exit 1; }
mkdir -p $O $T
rm -rf $H/base $H/branch && mkdir -p $H/base $H/branch
git -C "$R" archive "$MAIN" | tar -x -C $H/base
git -C "$R" archive "$BR" | tar -x -C $H/branch
for X in base branch; do [ -d $H/$X/src/sdn3d ] || { echo "no src in $H/$X" >&2; exit 1; }; done
grep -q _fan_labels $H/branch/src/sdn3d/editing/photo/transfer.py || { echo "branch tree lacks _fan_labels" >&2; exit 1; }
grep -q part_smoothing $H/base/src/sdn3d/editing/photo/settings.py && { echo "base tree has part_smoothing" >&2; exit 1; }
echo "start main $MAIN branch $BR $(date -u +%T)" >> $H/held.log
(PYTHONPATH=$H/base/src OMP_NUM_THREADS=1 nice -n 5 \
  /work/main/.venv/bin/python $D/gen_cf.py $H/tree2291 2291 0001,0002,0006,0018,0020 8 > $H/gen2291.log 2>&1)
echo "generated rc=$? $(date -u +%T)" >> $H/held.log
for S in oracle semantic; do
  bash $D/cf_turns.sh $H/base $H/tree2291 $O/main_$S $S >> $H/held.log
  bash $D/cf_turns.sh $H/branch $H/tree2291 $O/branch_$S $S >> $H/held.log
done
cd $O && PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/paired.py cf2291 main_oracle branch_oracle > $T/heldout2291.md
PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/paired.py cf2291 main_semantic branch_semantic | tail -n +3 >> $T/heldout2291.md
for S in oracle semantic; do
  PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/exact.py main_$S branch_$S
done > $T/heldout2291_exact.txt
for S in oracle semantic; do PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/percar.py main_$S branch_$S; done > $T/heldout2291_percar.md
PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/flatcheck.py main_oracle branch_oracle main_semantic branch_semantic > $T/heldout2291_flat_pairs.txt
echo "done $(date -u +%T)" >> $H/held.log
cp $H/gen2291.log $H/held.log $T/
