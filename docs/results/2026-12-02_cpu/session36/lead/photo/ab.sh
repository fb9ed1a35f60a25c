# ab.sh ROUNDS OUT: the photo stage's ms per edit (sdn3d-edit's own "photo N ms"), base worktree (main 5d254108)
# against the working tree, alternated within each round; real frame, boxes, w36, one thread
cd /work/main
for r in $(seq 1 $1); do
  for s in t1 t1_180 t2 t2_45 d1; do
    for v in base new; do
      [ $v = base ] && pp=/tmp/s36_lead_base/src || pp=/work/main/src
      ms=$(PYTHONPATH=$pp OMP_NUM_THREADS=1 .venv/bin/python -m sdn3d.cli.edit input.image=tests/data/0006_30-deg-right_00043.png edits=docs/results/2026-12-02_cpu/session35/lead/nearest/photo/$s.yaml run=/tmp/w36/outputs/demo/runs proposals=boxes threads=1 output_dir=/tmp/s36/photo/ab/$v/$s overwrite=true progress=false 2>&1 | grep -o "photo [0-9]* ms" | grep -o "[0-9]*")
      echo "$r $s $v $ms" >> $2
    done
  done
done
