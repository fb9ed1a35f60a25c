#!/bin/bash
# side_by_side.sh ROUNDS: the real frame (tests/data, 1242x375), both cars from boxes turned -90 degrees (spec.yaml),
# weights w33, one torch thread: the photo stage's time (sdn3d-edit's summary line, "photo N ms") of the code before
# the kernel (BEFORE: plain tree of 8111c8cf) and with it (AFTER: plain tree of 4f1c31a9), part smoothing on and
# off, alternated: each round runs before-on, after-on, before-off, after-off.
HERE=$(cd "$(dirname "$0")" && pwd); BEFORE=/tmp/s33/nk/before; AFTER=/tmp/s33/nk/after; OUT=/tmp/s33/nk/sbs
for r in $(seq 1 ${1:-3}); do
  for sm in true false; do
    for name in before after; do
      T=$BEFORE; [ $name = after ] && T=$AFTER
      ms=$(cd $T && PYTHONPATH=$T/src SDN3D_CONFIG_DIR=$T/conf OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit \
        input.image=/work/main/tests/data/0006_30-deg-right_00043.png edits=$HERE/spec.yaml \
        run=/tmp/s33/democlone/outputs/demo/runs proposals=boxes threads=1 output_dir=$OUT/${name}_$sm overwrite=true \
        progress=false photo.part_smoothing=$sm 2>&1 | grep -o "photo [0-9]* ms" | grep -o "[0-9]*")
      echo "round $r smoothing=$sm $name photo_ms=$ms load=$(cut -d' ' -f1 /proc/loadavg)"
    done
  done
done
