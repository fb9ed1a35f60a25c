#!/bin/bash
# runset.sh NAME PROPOSALS ARGS... : one cached tuning run on t1_31
name=$1; props=$2; shift 2
PYTHONPATH=/work/main/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s4data/lead/cached_bench.py /tmp/s4data/lead/cache31 data.root=/tmp/s4data/lead/t1_31 'data.image_size=[312,96]' run=/work/final_demo 'compose=[photo]' "proposals=[$props]" threads=1 examples=0 output_dir=/tmp/s4data/lead/runs/$name "$@" > /tmp/s4data/lead/$name.log 2>&1
