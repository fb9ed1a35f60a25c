#!/bin/bash
# heldrun.sh SRC TAG : Table 1 photo rows on the held-out tree t1_2067 (gt, semantic, oracle), own cache per TAG
src=$1; tag=$2
for sc in "gt derender" "semantic derender" "gt oracle"; do set -- $sc
PYTHONPATH=$src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s5data/lead/cached_bench.py /tmp/s5data/lead/held/cache_$tag data.root=/tmp/s5data/lead/t1_2067 'data.image_size=[312,96]' run=/work/final_demo 'compose=[photo]' "proposals=[$1]" scene=$2 threads=1 examples=0 output_dir=/tmp/s5data/lead/held/${tag}_$1_$2 > /tmp/s5data/lead/held/${tag}_$1_$2.log 2>&1
done
