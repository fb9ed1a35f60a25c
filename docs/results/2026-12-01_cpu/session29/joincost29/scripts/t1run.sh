#!/bin/bash
# t1run.sh: Table 1's predicted row (photo) of tree 11's entries whose source frame has the join that is not bit-equal
# (0001/rain/00034: entries 30, 40, 45), main's tree and the branch's, session 28 merge40's dbench.py (w28, 312x96,
# fresh caches); outputs /tmp/s29/joincost29/t1/<code>.
DBENCH=/work/wt/joincost29/docs/results/2026-12-01_cpu/session28/merge40/scripts/dbench.py
OUT=/tmp/s29/joincost29/t1; mkdir -p $OUT
for C in main:/tmp/s29/joincost29/base branch:/tmp/s29/joincost29/branch1; do
  N=${C%%:*}; D=${C#*:}
  (cd $D && ONLY=30,40,45 PYTHONPATH=$D/src SDN3D_CONFIG_DIR=$D/conf OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
     $DBENCH $OUT/cache_$N $OUT/$N.dump data.root=/tmp/s28/merge40/trees/t1_11 'data.image_size=[312,96]' \
     run=/tmp/s28/demo2/outputs/demo 'compose=[photo]' 'proposals=[semantic]' scene=derender threads=1 examples=0 \
     output_dir=$OUT/$N > $OUT/$N.log 2>&1)
  echo "$N rc=$? $(date -u +%T)" >> $OUT/t1.log
done
