#!/bin/bash
# call.sh TREE OUTDIR THREADS [phases.json] [RUNS]: one sdn3d-edit call (t1_31 0001/clone/00000, spec31: 10 boxes + a rotate)
S4=/work/main/docs/results/2026-11-28_cpu/session4/cost; IMG=/tmp/s11data/lead/t1_31/vkitti_1.3.1_rgb/0001/clone/00000.png; PY=/work/main/.venv/bin/python
T=$1; O=$2; N=$3; R=${5:-/tmp/s11data/demo/out/runs}
if [ -n "$4" ]; then
  cd $T && PYTHONPATH=$T/src:$T SDN3D_CONFIG_DIR=$T/conf OMP_NUM_THREADS=$N nice -n 5 $PY benchmarks/edit_cost.py --out $4 -- run=$R input.image=$IMG edits=$S4/spec31.yaml output_dir=$O overwrite=true threads=$N $EXTRA >/dev/null 2>$4.err
else
  PYTHONPATH=$T/src SDN3D_CONFIG_DIR=$T/conf OMP_NUM_THREADS=$N nice -n 5 $PY -m sdn3d.cli.edit run=$R input.image=$IMG edits=$S4/spec31.yaml output_dir=$O overwrite=true threads=$N $EXTRA
fi
