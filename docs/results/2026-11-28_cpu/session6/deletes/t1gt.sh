#!/bin/bash
# t1gt.sh SRC NAME SCENES ARGS... : as t1run.sh for the listed source scenes only ("gt:derender,semantic:derender,gt:oracle")
src=$1; name=$2; scenes=$3; shift 3
extra=("$@")
for sc in ${scenes//,/ }; do p=${sc%%:*}; s=${sc##*:}
PYTHONPATH=$src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s5data/lead/cached_bench.py /tmp/s6data/deletes/cache31 data.root=/tmp/s4data/lead/t1_31 'data.image_size=[312,96]' run=/work/final_demo 'compose=[photo]' "proposals=[$p]" scene=$s threads=1 examples=0 output_dir=/tmp/s6data/deletes/runs/${name}_${p}_$s "${extra[@]}" > /tmp/s6data/deletes/runs/${name}_${p}_$s.log 2>&1
done
