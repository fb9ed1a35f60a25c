#!/bin/bash
# real_listing.sh CODE OUT: the real frame of tests/data (README's "Edit your own image": red car [466, 203, 666,
# 333], black car [704, 194, 917, 305]) listed by sdn3d-edit of the code tree CODE (no edit: the fitted poses),
# weights w0, threads 1. OUT/objects.json holds each car's fitted yaw.
CODE=$1; OUT=$2; mkdir -p $(dirname $OUT)
printf 'objects:\n- box: [466, 203, 666, 333]\n  class: Car\n- box: [704, 194, 917, 305]\n  class: Car\nops: []\n' \
  > $OUT.yaml
cd $CODE && PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.edit \
  input.image=$CODE/tests/data/0006_30-deg-right_00043.png run=/tmp/s21data/demo/out proposals=boxes \
  edits=$OUT.yaml output_dir=$OUT threads=1
