#!/bin/bash
# One sdn3d-edit call at 624x192 with 10 box objects (seed-31 tuning frame, session 4's spec, threads=2): this branch
# (A) against its base fc6b2b7 (B), whole-process pairs A B A B ..., the load before and after.
S4=/tmp/s4data/cost; O=/tmp/s8data/editcall; IMG=$S4/dense31/vkitti_1.3.1_rgb/0006/clone/00000.png; PY=/work/main/.venv/bin/python
A=$O/final; B=$O/base; T=${T:-2}
uptime; ps -eo pcpu,etime,args --sort=-pcpu | head -8 | cut -c1-140
farm-bench -n ${N:-3} --warmup ${W:-1} --timeout 1800 \
  --vs "env PYTHONPATH=$B/src SDN3D_CONFIG_DIR=$B/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/edit_before_t$T overwrite=true threads=$T" \
  -- env PYTHONPATH=$A/src SDN3D_CONFIG_DIR=$A/conf SDN3D_NATIVE_CACHE=$O/native OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/edit_after_t$T overwrite=true threads=$T
uptime
