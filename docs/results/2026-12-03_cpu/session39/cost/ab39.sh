#!/bin/bash
# ab39.sh ROUNDS OUT (env BASE, NEW: the two code trees; default /work/wt_base, /work/wt_new): session 38's ab.sh with this session's paths: the photo stage's ms per edit (sdn3d-edit's own
# "photo N ms" and its CPU ms, session 38's timed_edit.py), base b406c7b1 (/work/wt_base, before the sharp lane prior)
# against b3e96112 (/work/wt_new), alternated within each round (order flipped every other round); the real frame of
# tests/data, boxes, weights w39, one thread; specs of session 35 (t1 / t1_180: red car turned -90 / 180; t2 / t2_45:
# black car turned -90 / 45; d1: a delete). Lines: round, spec, arm, wall ms, CPU ms.
cd /work/main
rounds=$1 out=$2
for r in $(seq 1 $rounds); do
  for s in t1 t1_180 t2 t2_45 d1; do
    [ $((r % 2)) = 1 ] && order="base new" || order="new base"
    for v in $order; do
      [ $v = base ] && pp=${BASE:-/work/wt_base}/src || pp=${NEW:-/work/wt_new}/src
      log=$(PYTHONPATH=$pp OMP_NUM_THREADS=1 /work/main/.venv/bin/python docs/results/2026-12-02_cpu/session38/perf/timed_edit.py input.image=tests/data/0006_30-deg-right_00043.png edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/$s.yaml run=/tmp/w39/outputs/demo/runs proposals=boxes threads=1 output_dir=/tmp/s39photo/$v/$s overwrite=true progress=false 2>&1)
      ms=$(echo "$log" | grep -o "photo [0-9]* ms" | grep -o "[0-9]*")
      cpu=$(echo "$log" | grep -o "photo cpu [0-9]* ms" | grep -o "[0-9]*")
      echo "$r $s $v $ms $cpu" >> $out
    done
  done
done
