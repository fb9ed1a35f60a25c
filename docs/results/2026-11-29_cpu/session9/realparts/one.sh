#!/bin/bash
# (session 9 realparts record; /tmp/s9data/realparts is the work dir)
# one.sh TREE OUT IID OPYAML [overrides]  -> runs one edit on the real frame with boxes
TREE=$1; OUT=$2; IID=$3; OP=$4; shift 4
mkdir -p $OUT
cat > $OUT/spec.yaml <<EOS
objects:
- {box: [466, 203, 666, 333], class: Car}
- {box: [704, 194, 917, 305], class: Car}
ops:
- {op: $OP, id: $IID}
EOS
cd $TREE && PYTHONPATH=$TREE/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit input.image=/work/main/tests/data/0006_30-deg-right_00043.png run=/tmp/s5data/lead/demo/runs proposals=boxes edits=$OUT/spec.yaml output_dir=$OUT/out "$@" > $OUT/log.txt 2>&1
echo rc=$?
