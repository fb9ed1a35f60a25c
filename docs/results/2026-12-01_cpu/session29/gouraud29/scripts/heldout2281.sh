#!/bin/bash
# heldout2281.sh BRANCH_COMMIT: the held-out tree (seed 2281, gen_cf.py's recipe: worlds 0006,0018,0020, 6 cars, main's
# generator), generated once after the merge rule's commit, measured once: main bbdcb5ac (a plain tree,
# /tmp/s29/gouraud29/base) against BRANCH_COMMIT (a plain tree of the whole commit, its defaults), counterfactual turns
# (cf_turns.sh: fill rays, w28), ground-truth geometry (oracle) and predicted, two at a time; then paired.py into
# tables/heldout2281.md. (session 29 smooth29's heldout2279.sh, paths and the setting's name changed.)
set -u
BR=$1; D=$(cd "$(dirname "$0")" && pwd); R=$(git -C "$D" rev-parse --show-toplevel); H=/tmp/s29/gouraud29; O=$H/cf
mkdir -p $O $H/base $H/branch
[ -d $H/base/src/sdn3d ] || git -C "$R" archive bbdcb5ac | tar -x -C $H/base
rm -rf $H/branch && mkdir -p $H/branch && git -C "$R" archive "$BR" | tar -x -C $H/branch
for T in base branch; do [ -d $H/$T/src/sdn3d ] || { echo "no src in $H/$T" >&2; exit 1; }; done
grep -q part_smoothing $H/branch/src/sdn3d/editing/photo/settings.py || { echo "branch tree lacks part_smoothing" >&2; exit 1; }
grep -q part_smoothing $H/base/src/sdn3d/editing/photo/settings.py && { echo "base tree has part_smoothing" >&2; exit 1; }
echo "start $BR $(date -u +%T)" >> $H/held.log
[ -e $H/tree2281/_SUCCESS ] || (PYTHONPATH=$H/base/src OMP_NUM_THREADS=1 nice -n 5 \
  /work/main/.venv/bin/python $D/gen_cf.py $H/tree2281 2281 0006,0018,0020 6 > $H/gen2281.log 2>&1)
echo "generated $(date -u +%T)" >> $H/held.log
for S in oracle semantic; do
  bash $D/cf_turns.sh $H/base $H/tree2281 $O/main_$S $S >> $H/held.log &
  bash $D/cf_turns.sh $H/branch $H/tree2281 $O/branch_$S $S >> $H/held.log
  wait
done
cd $O && PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/paired.py cf2281 main_oracle branch_oracle > $D/../tables/heldout2281.md
PYTHONPATH=$H/branch/src /work/main/.venv/bin/python $D/paired.py cf2281 main_semantic branch_semantic | tail -n +3 >> $D/../tables/heldout2281.md
echo "done $(date -u +%T)" >> $H/held.log
