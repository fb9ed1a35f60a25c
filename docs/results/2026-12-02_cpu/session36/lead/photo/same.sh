# same.sh: the six real-frame edits with the base worktree and with /work/main; cmp of edited.png
cd /work/main
for s in t1 t1_180 t2 t2_45 d1 d2; do
  for v in base new; do
    [ $v = base ] && pp=/tmp/s36_lead_base/src || pp=/work/main/src
    [ $v = base ] && [ -e /tmp/s36/photo/same/base/$s/edited.png ] && continue
    PYTHONPATH=$pp OMP_NUM_THREADS=1 .venv/bin/python -m sdn3d.cli.edit input.image=tests/data/0006_30-deg-right_00043.png edits=docs/results/2026-12-02_cpu/session35/lead/nearest/photo/$s.yaml run=/tmp/w36/outputs/demo/runs proposals=boxes threads=1 output_dir=/tmp/s36/photo/same/$v/$s overwrite=true progress=false > /dev/null 2>&1 || echo "$s $v failed"
  done
  cmp -s /tmp/s36/photo/same/base/$s/edited.png /tmp/s36/photo/same/new/$s/edited.png && echo "$s identical" || echo "$s DIFFERENT"
done
