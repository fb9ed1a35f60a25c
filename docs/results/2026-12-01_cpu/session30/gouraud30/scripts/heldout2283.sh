#!/bin/bash
# heldout2283.sh BRANCH_COMMIT: the held-out tree (seed 2283, gen_cf.py's recipe with worlds 0001,0002,0006,0018,0020
# and 8 cars, main's generator), generated once after the merge rule's commit, measured once: main 26c3e568 (a plain
# tree, /tmp/s30/gouraud30/base, `git archive main`) against BRANCH_COMMIT (a plain tree of the whole commit, its
# defaults), counterfactual turns (cf_turns.sh: fill rays, w30), ground-truth geometry (oracle) and predicted, two at a
# time; then paired.py (car-clustered intervals, pairs beside), exact.py, percar.py, flatcheck.py into tables/.
# (session 29 gouraud29's heldout2281.sh, seed, worlds, cars and paths changed.)
set -u
BR=$1; D=$(cd "$(dirname "$0")" && pwd); R=$(git -C "$D" rev-parse --show-toplevel); H=/tmp/s30/gouraud30; O=$H/cf
T=$D/../tables
mkdir -p $O $H/base $H/branch $T
[ -d $H/base/src/sdn3d ] || git -C "$R" archive 26c3e568 | tar -x -C $H/base
rm -rf $H/branch && mkdir -p $H/branch && git -C "$R" archive "$BR" | tar -x -C $H/branch
for X in base branch; do [ -d $H/$X/src/sdn3d ] || { echo "no src in $H/$X" >&2; exit 1; }; done
grep -q _fan_labels $H/branch/src/sdn3d/editing/photo/transfer.py || { echo "branch tree lacks _fan_labels" >&2; exit 1; }
grep -q part_smoothing $H/base/src/sdn3d/editing/photo/settings.py && { echo "base tree has part_smoothing" >&2; exit 1; }
echo "start $BR $(date -u +%T)" >> $H/held.log
[ -e $H/tree2283/_SUCCESS ] || (PYTHONPATH=$H/base/src OMP_NUM_THREADS=1 nice -n 5 \
  /work/main/.venv/bin/python $D/gen_cf.py $H/tree2283 2283 0001,0002,0006,0018,0020 8 > $H/gen2283.log 2>&1)
echo "generated $(date -u +%T)" >> $H/held.log
for S in oracle semantic; do
  bash $D/cf_turns.sh $H/base $H/tree2283 $O/main_$S $S >> $H/held.log &
  bash $D/cf_turns.sh $H/branch $H/tree2283 $O/branch_$S $S >> $H/held.log
  wait
done
cd $O && PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/paired.py cf2283 main_oracle branch_oracle > $T/heldout2283.md
PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/paired.py cf2283 main_semantic branch_semantic | tail -n +3 >> $T/heldout2283.md
for S in oracle semantic; do
  PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/exact.py main_$S branch_$S
done > $T/heldout2283_exact.txt
for S in oracle semantic; do PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/percar.py main_$S branch_$S; done > $T/heldout2283_percar.md
PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/flatcheck.py main_oracle branch_oracle main_semantic branch_semantic > $T/heldout2283_flat_pairs.txt
cp $H/gen2283.log $H/held.log $T/
echo "done $(date -u +%T)" >> $H/held.log
