#!/bin/bash
# alternating base/mine: whole-process time (wall, user, sys, faults) and the staged timing of _refine_box_masks
A="input.image=/tmp/s40speed/in624.png threads=2 run=/tmp/w39/outputs/demo/runs edits=/work/main/docs/results/2026-12-03_cpu/session39/cost/spec31_w38.yaml"
cd /work/wt_speed
for i in $(seq 1 $1); do
  for who in base mine; do
    if [ $who = base ]; then SRC=/tmp/s40speed/base/src; else SRC=/work/wt_speed/src; fi
    /usr/bin/time -f "$who process wall %e user %U sys %S minflt %R" env PYTHONPATH=$SRC /work/main/.venv/bin/python -m sdn3d.cli.edit $A output_dir=/tmp/s40speed/out_p_$who 2>&1 | tail -1
    env OMP_WAIT_POLICY=PASSIVE PYTHONPATH=$SRC /work/main/.venv/bin/python /tmp/s40speed/stages.py $A output_dir=/tmp/s40speed/out_s_$who 2>&1 | grep -E "_refine_box_masks|fit_box_objects|derender.derender" | sed "s/^/$who stage /"
  done
done
