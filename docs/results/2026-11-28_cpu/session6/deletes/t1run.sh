#!/bin/bash
# t1run.sh SRC NAME ARGS... : Table 1 photo rows on the tuning tree t1_31 for three source scenes
# (ground-truth masks: gt derender; predicted proposals: semantic derender; ground-truth geometry: gt oracle), cached
src=$1; name=$2; shift 2
extra=("$@")
for sc in "gt derender" "semantic derender" "gt oracle"; do set -- $sc
PYTHONPATH=$src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s5data/lead/cached_bench.py /tmp/s6data/deletes/cache31 data.root=/tmp/s4data/lead/t1_31 'data.image_size=[312,96]' run=/work/final_demo 'compose=[photo]' "proposals=[$1]" scene=$2 threads=1 examples=0 output_dir=/tmp/s6data/deletes/runs/${name}_$1_$2 "${extra[@]}" > /tmp/s6data/deletes/runs/${name}_$1_$2.log 2>&1
done
