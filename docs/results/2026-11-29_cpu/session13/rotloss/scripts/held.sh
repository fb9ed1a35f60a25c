#!/bin/bash
# held.sh: held-out seed 2123, generated after the code was final (no library change: the branch's library is main's,
# 97b891e), with session 9 fogflip's gen_t1.py recipe (the tuning trees'), measured once: main's Table 1 photo rows,
# semantic proposals and ground-truth masks (oracle), session 11's demo weights; then the per-entry poses and causes.
T=/tmp/s13data/rotloss; W=/work/wt/rotloss; S=$W/docs/results/2026-11-29_cpu/session13/rotloss/scripts
cd $T/base && PYTHONPATH=$T/base/src:$T/base OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $W/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py $T/t1_2123 2123 > $T/gen2123.log 2>&1
$S/run.sh $T/base h2123_semantic $T/t1_2123 semantic $T/cache_h2123
$S/run.sh $T/base h2123_gt $T/t1_2123 gt $T/cache_h2123
for p in semantic gt; do
  cd $T/base && PYTHONPATH=$T/base/src:$T/base OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $S/poses.py $T/runs/h2123_$p $T/runs/h2123_$p.dump $T/cache_h2123 $T/t1_2123 $T/poses_h2123_$p.json > $T/poses_h2123_$p.txt 2>&1
done
echo held done
