#!/bin/bash
# One sdn3d-edit call at 624x192 with session 4's 10 boxes (spec31.yaml) on tuning frame t1_31 0001/clone/00000, session
# 11's demo weights, idle machine: A = main after session 12's merges, B = the session start 01655bc (git archive).
# Session 11's edit_ab.sh with the session-12 paths; both trees byte-compiled first (PYTHONDONTWRITEBYTECODE is set here).
S4=/work/main/docs/results/2026-11-28_cpu/session4/cost; O=/tmp/s12data/lead/edit_ab; IMG=/tmp/s11data/lead/t1_31/vkitti_1.3.1_rgb/0001/clone/00000.png; PY=/work/main/.venv/bin/python
A=/work/main; B=/tmp/s12data/lead/base_016; T=${T:-2}; R=/tmp/s11data/demo/out/runs
$PY -m compileall -q $A/src $B/src
uptime
farm-bench -n ${N:-5} --warmup ${W:-1} --timeout 1800 \
  --vs "env PYTHONPATH=$B/src SDN3D_CONFIG_DIR=$B/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=$R input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/before_t$T overwrite=true threads=$T" \
  -- env PYTHONPATH=$A/src SDN3D_CONFIG_DIR=$A/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=$R input.image=$IMG edits=$S4/spec31.yaml output_dir=$O/after_t$T overwrite=true threads=$T
uptime
