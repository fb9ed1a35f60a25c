# ruff: noqa: INP001, E501
# same.sh: the five real-frame edits with the base worktree and with /work/wt_photo (or $NEW, a snapshot of its code);
# cmp of edited.png
cd /work/wt_photo
new=${NEW:-/work/wt_photo/src}
for s in t1 t1_180 t2 t2_45 d1; do
  for v in base new; do
    [ $v = base ] && pp=/work/wt_photo_base/src || pp=$new
    PYTHONPATH=$pp OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit input.image=tests/data/0006_30-deg-right_00043.png edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/$s.yaml run=/tmp/w38/outputs/demo/runs proposals=boxes threads=1 output_dir=/tmp/s38photo/same/$v/$s overwrite=true progress=false > /dev/null 2>&1 || echo "$s $v failed"
  done
  cmp -s /tmp/s38photo/same/base/$s/edited.png /tmp/s38photo/same/new/$s/edited.png && echo "$s identical" || echo "$s DIFFERENT"
done
