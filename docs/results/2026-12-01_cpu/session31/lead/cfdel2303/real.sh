#!/bin/bash
# real.sh OUT CODE RUN: session 11's real-frame deletes (fill2/real.sh) on the frame of tests/data, boxes, each car
# deleted with photo.fill=rays and with photo.fill=learnt (the packaged nets), code CODE (a plain tree), weights RUN.
OUT=$1; WT=$2; RUN=$3
for IID in 12001 12002; do for FILL in rays learnt; do
  D=$OUT/${IID}_$FILL; mkdir -p $D
  printf 'objects:\n- {box: [466, 203, 666, 333], class: Car}\n- {box: [704, 194, 917, 305], class: Car}\nops:\n- {op: delete, id: %s}\n' $IID > $D/spec.yaml
  (cd $WT && PYTHONPATH=$WT/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.edit \
    input.image=$WT/tests/data/0006_30-deg-right_00043.png run=$RUN proposals=boxes \
    edits=$D/spec.yaml output_dir=$D/out photo.fill=$FILL > $D/log.txt 2>&1; echo "$IID $FILL rc=$?")
done; done
