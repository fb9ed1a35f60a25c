# ruff: noqa: INP001, E501
# ab.sh ROUNDS OUT [SPEC...]: the photo stage's ms per edit (sdn3d-edit's own "photo N ms"), the base worktree (main 9bd07c21,
# at /work/wt_photo_base) against /work/wt_photo (or $NEW), alternated within each round (the order flipped every
# other round); real frame, boxes, the demo's weights w38, one thread; lines: round, spec, base or new, the photo
# stage's wall ms (sdn3d-edit's own) and its CPU ms (timed_edit.py)
cd /work/wt_photo
rounds=$1 out=$2
shift 2
specs="$*"
new=${NEW:-/work/wt_photo/src}  # the code under test (a snapshot of it, while the tree changes)
for r in $(seq 1 $rounds); do
  for s in ${specs:-t1 t1_180 t2 t2_45 d1}; do
    [ $((r % 2)) = 1 ] && order="base new" || order="new base"
    for v in $order; do
      [ $v = base ] && pp=/work/wt_photo_base/src || pp=$new
      log=$(PYTHONPATH=$pp OMP_NUM_THREADS=1 /work/main/.venv/bin/python docs/results/2026-12-02_cpu/session38/perf/timed_edit.py input.image=tests/data/0006_30-deg-right_00043.png edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/$s.yaml run=/tmp/w38/outputs/demo/runs proposals=boxes threads=1 output_dir=/tmp/s38photo/ab/$v/$s overwrite=true progress=false 2>&1)
      ms=$(echo "$log" | grep -o "photo [0-9]* ms" | grep -o "[0-9]*")
      cpu=$(echo "$log" | grep -o "photo cpu [0-9]* ms" | grep -o "[0-9]*")
      echo "$r $s $v $ms $cpu" >> $out
    done
  done
done
