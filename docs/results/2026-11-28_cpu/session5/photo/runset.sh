#!/bin/bash
# runset.sh SRC NAME PROPOSALS SCENE ARGS... : one cached tuning run on t1_31 (SRC: a src dir)
src=$1; name=$2; props=$3; scene=$4; shift 4
PYTHONPATH=$src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s5data/lead/cached_bench.py /tmp/s5data/lead/cache31 data.root=/tmp/s4data/lead/t1_31 'data.image_size=[312,96]' run=/work/final_demo 'compose=[photo]' "proposals=[$props]" scene=$scene threads=1 examples=0 output_dir=/tmp/s5data/lead/runs/$name "$@" > /tmp/s5data/lead/$name.log 2>&1
