#!/bin/bash
# call.sh TREE OUTDIR THREADS [phases.json]: one sdn3d-edit call (seed-31 frame, spec31: 10 boxes + a rotate)
S4=/tmp/s4data/cost; IMG=$S4/dense31/vkitti_1.3.1_rgb/0006/clone/00000.png; PY=/work/main/.venv/bin/python
T=$1; O=$2; N=$3
if [ -n "$4" ]; then
  cd $T && PYTHONPATH=$T/src:$T SDN3D_CONFIG_DIR=$T/conf OMP_NUM_THREADS=$N $PY benchmarks/edit_cost.py --out $4 -- run=/work/final_demo/runs input.image=$IMG edits=$S4/spec31.yaml output_dir=$O overwrite=true threads=$N $EXTRA >/dev/null 2>$4.err
else
  PYTHONPATH=$T/src SDN3D_CONFIG_DIR=$T/conf OMP_NUM_THREADS=$N $PY -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=$S4/spec31.yaml output_dir=$O overwrite=true threads=$N $EXTRA >/dev/null 2>&1
fi
