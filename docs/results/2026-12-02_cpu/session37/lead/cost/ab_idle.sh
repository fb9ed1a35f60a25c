# ab_idle.sh ROUNDS OUT: the photo stage's ms per edit (sdn3d-edit's "photo N ms"), main before the photo speed-ups
# (ce949f01, /tmp/s37_base) against the final main (/work/main), alternated within each round (order flipped every
# other round), on the machine with nothing else running; real frame, boxes, weights w37, one thread.
cd /work/main
for r in $(seq 1 $1); do
  for s in t1 t1_180 t2 t2_45 d1; do
    [ $((r % 2)) = 1 ] && order="base new" || order="new base"
    for v in $order; do
      [ $v = base ] && pp=/tmp/s37_base/src || pp=/work/main/src
      ms=$(PYTHONPATH=$pp OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit input.image=tests/data/0006_30-deg-right_00043.png edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/$s.yaml run=/tmp/w37/outputs/demo/runs proposals=boxes threads=1 output_dir=/tmp/s37/ab/$v/$s overwrite=true progress=false 2>&1 | grep -o "photo [0-9]* ms" | grep -o "[0-9]*")
      echo "$r $s $v $ms" >> $2
    done
  done
done
