#!/bin/bash
# real.sh OUT WEIGHTS: the real frame of tests/data (boxes, demo weights /tmp/s5data/lead/demo/runs), each car deleted
# with photo.fill=rays and photo.fill=learnt (photo.learnt_weights=WEIGHTS).
OUT=$1; W=$2; WT=$(cd "$(dirname "$0")/../../../../.." && pwd)
for IID in 12001 12002; do for FILL in rays learnt; do
  D=$OUT/${IID}_$FILL; mkdir -p $D
  cat > $D/spec.yaml <<EOS
objects:
- {box: [466, 203, 666, 333], class: Car}
- {box: [704, 194, 917, 305], class: Car}
ops:
- {op: delete, id: $IID}
EOS
  (cd $WT && PYTHONPATH=$WT/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit \
    input.image=$WT/tests/data/0006_30-deg-right_00043.png run=/tmp/s5data/lead/demo/runs proposals=boxes \
    edits=$D/spec.yaml output_dir=$D/out photo.fill=$FILL photo.learnt_weights=$W > $D/log.txt 2>&1; echo "$IID $FILL rc=$?")
done; done
