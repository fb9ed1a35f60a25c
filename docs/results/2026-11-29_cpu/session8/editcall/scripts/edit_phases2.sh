#!/bin/bash
# Per-phase CPU / wall seconds of one sdn3d-edit call (benchmarks/edit_cost.py), before (base fc6b2b7) and after
# (this branch), alternating, R rounds; threads=2. Seed-31 tuning frame, session 4's spec.
S4=/tmp/s4data/cost; O=/tmp/s8data/editcall; IMG=$S4/dense31/vkitti_1.3.1_rgb/0006/clone/00000.png; PY=/work/main/.venv/bin/python
OUT=${OUT:-$O/phases}; mkdir -p $OUT
for i in $(seq 1 ${R:-2}); do
  for side in before after; do
    T=$O/base; [ $side = after ] && T=$O/${ATREE:-final}
    uptime >> $OUT/load.txt
    PYTHONPATH=$T/src SDN3D_CONFIG_DIR=$T/conf SDN3D_NATIVE_CACHE=$O/native OMP_NUM_THREADS=${TH:-2} $PY $T/benchmarks/edit_cost.py --out $OUT/${side}_$i.json -- run=/work/final_demo/runs input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/edit_$side overwrite=true threads=${TH:-2} > $OUT/${side}_$i.log 2>&1
  done
done
uptime >> $OUT/load.txt
