#!/bin/bash
for c in 8ec52ae fd23a7e 8198e67 d482cff; do
PYTHONPATH=/tmp/s5data/lead/bis/$c/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s5data/lead/cached_bench.py /tmp/s5data/lead/cache31f data.root=/tmp/s4data/lead/t1_31 'data.image_size=[312,96]' run=/work/final_demo 'compose=[photo]' "proposals=[gt]" scene=derender threads=1 examples=0 limit=30 output_dir=/tmp/s5data/lead/runs/bis_$c > /tmp/s5data/lead/bis_$c.log 2>&1
done
