#!/bin/bash
# Table 1 photo mode on the seed-31 tuning tree (/tmp/s4data/deletes/t1_31): main (774bffb) vs candidate
who=$1; DIR=/tmp/s5data/deletes/$who
cd $DIR && PYTHONPATH=$DIR/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=/tmp/s4data/deletes/t1_31 scene=oracle 'proposals=[gt]' 'compose=[photo]' examples=0 \
    checkpoints.textural=/work/final_demo/runs/textural/checkpoints/inference.pt output_dir=/tmp/s5data/deletes/t1_31_$who > /tmp/s5data/deletes/t1_31_$who.log 2>&1
echo done $who
