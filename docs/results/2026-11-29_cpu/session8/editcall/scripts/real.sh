#!/bin/bash
# The real frame in tests/data with the README's two boxes (proposals=boxes), the demo weights, threads=1: base and
# this branch (session 5 and 6's check of the real photo's fit).
O=/tmp/s8data/editcall; PY=/work/main/.venv/bin/python
printf 'objects:\n  - {box: [466, 203, 666, 333], class: Car}\n  - {box: [704, 194, 917, 305], class: Car}\n' > $O/real_boxes.yaml
for side in base final; do
  T=$O/$side
  PYTHONPATH=$T/src SDN3D_CONFIG_DIR=$T/conf SDN3D_NATIVE_CACHE=$O/native OMP_NUM_THREADS=1 $PY -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$T/tests/data/0006_30-deg-right_00043.png proposals=boxes edits=$O/real_boxes.yaml output_dir=$O/real_$side overwrite=true threads=1 > $O/real_$side.log 2>&1
done
