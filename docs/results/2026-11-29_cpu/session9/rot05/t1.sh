#!/bin/bash
# t1.sh CODE_DIR OUT: Table 1 bench on the tuning tree t1_31 (session 4's), ground-truth geometry oracle source
# (proposals=gt, scene=oracle), demo weights of session 5, 312x96 as session 8's capture; code CODE_DIR (src + conf)
code=$1; out=$2
cd $code && PYTHONPATH=$code/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=/tmp/s4data/lead/t1_31 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' 'proposals=[gt]' scene=oracle threads=1 examples=0 output_dir=$out > $out.log 2>&1
echo "done $out rc=$?"
