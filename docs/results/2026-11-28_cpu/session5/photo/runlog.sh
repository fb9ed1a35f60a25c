#!/bin/bash
# runlog.sh NAME PROPOSALS SCENE ARGS... : cached tuning run on t1_31 with main's src, objects logged
name=$1; props=$2; scene=$3; shift 3
LOG=/tmp/s5data/lead/$name.jsonl PYTHONPATH=/work/main/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s5data/lead/logobj_bench.py /tmp/s5data/lead/cache31 data.root=/tmp/s4data/lead/t1_31 'data.image_size=[312,96]' run=/work/final_demo 'compose=[photo]' "proposals=[$props]" scene=$scene threads=1 examples=0 output_dir=/tmp/s5data/lead/runs/$name "$@" > /tmp/s5data/lead/$name.log 2>&1
