# ab.sh ROUNDS OUT: the photo stage's ms per edit (sdn3d-edit's own "photo N ms"), base worktree (s37-perf's base,
# main 1392c85b, at /tmp/s37perf_base) against /work/wt_perf, alternated within each round (the order flipped every
# other round); real frame, boxes, the demo's weights w37, one thread
cd /work/wt_perf
for r in $(seq 1 $1); do
  for s in t1 t1_180 t2 t2_45 d1; do
    [ $((r % 2)) = 1 ] && order="base new" || order="new base"
    for v in $order; do
      [ $v = base ] && pp=/tmp/s37perf_base/src || pp=/work/wt_perf/src
      ms=$(PYTHONPATH=$pp OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit input.image=tests/data/0006_30-deg-right_00043.png edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/$s.yaml run=/tmp/w37/outputs/demo/runs proposals=boxes threads=1 output_dir=/tmp/s37perf/ab/$v/$s overwrite=true progress=false 2>&1 | grep -o "photo [0-9]* ms" | grep -o "[0-9]*")
      echo "$r $s $v $ms" >> $2
    done
  done
done
