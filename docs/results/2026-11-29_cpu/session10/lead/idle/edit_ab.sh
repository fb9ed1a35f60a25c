#!/bin/bash
# One sdn3d-edit call at 624x192 with 10 box objects (seed-31 tuning frame, session 4's spec), threads=2, idle machine:
# A = main after session 10s merges, B = the session start f42d17c (git archive); farm-bench pairs A B A B ...
S4=/tmp/s4data/cost; O=/tmp/s10data/lead/idle/edit_ab; IMG=$S4/dense31/vkitti_1.3.1_rgb/0006/clone/00000.png; PY=/work/main/.venv/bin/python
A=/work/main; B=/tmp/s10data/lead/base_f42; T=${T:-2}
uptime
farm-bench -n ${N:-5} --warmup ${W:-1} --timeout 1800 \
  --vs "env PYTHONPATH=$B/src SDN3D_CONFIG_DIR=$B/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/before_t$T overwrite=true threads=$T" \
  -- env PYTHONPATH=$A/src SDN3D_CONFIG_DIR=$A/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/after_t$T overwrite=true threads=$T
uptime
