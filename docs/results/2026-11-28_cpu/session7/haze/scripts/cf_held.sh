#!/bin/bash
# held-out counterfactual deletes (seed 2085, clear/fog/rain, ground-truth geometry): session start (f45beb0, /work/main,
# read-only) with its defaults; final (src_final = dc1e333) with its defaults and with photo.ray_haze=0
r=/tmp/s7data/haze/cf2085
cd /work/main && PYTHONDONTWRITEBYTECODE=1 PYTHONPATH=/work/main/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s7data/haze/cf_diag.py $r /tmp/s7data/haze/cf2085_start.json start start > /tmp/s7data/haze/cf2085_start.log 2>&1; echo start $?
cd /tmp/s7data/haze/src_final && PYTHONDONTWRITEBYTECODE=1 PYTHONPATH=/tmp/s7data/haze/src_final/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s7data/haze/cf_diag.py $r /tmp/s7data/haze/cf2085_final.json final final final0:ray_haze=0 > /tmp/s7data/haze/cf2085_final.log 2>&1; echo final $?
