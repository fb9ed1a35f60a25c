#!/bin/bash
# One sdn3d-edit call at 624x192 with session 4's 10 boxes (spec31.yaml) on tuning frame t1_31 0001/clone/00000 with
# session 11's demo weights (the lead's call, session11/lead/idle/edit_ab.sh): A = this branch (ATREE, default
# /work/wt/speed), B = main at the session start 01655bc (git archive in /tmp/s12data/speed/base); farm-bench pairs
# A B A B ...; both trees byte-compiled beforehand (python -m compileall src).
S4=/work/main/docs/results/2026-11-28_cpu/session4/cost; O=/tmp/s12data/speed/ab; IMG=/tmp/s11data/lead/t1_31/vkitti_1.3.1_rgb/0001/clone/00000.png; PY=/work/main/.venv/bin/python
A=${ATREE:-/work/wt/speed}; B=/tmp/s12data/speed/base; T=${T:-2}; R=/tmp/s11data/demo/out/runs
uptime
nice -n 5 farm-bench -n ${N:-3} --warmup ${W:-1} --timeout 1800 \
  --vs "env PYTHONPATH=$B/src SDN3D_CONFIG_DIR=$B/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=$R input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/before_t$T overwrite=true threads=$T" \
  -- env PYTHONPATH=$A/src SDN3D_CONFIG_DIR=$A/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=$R input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/after_t$T overwrite=true threads=$T
uptime
