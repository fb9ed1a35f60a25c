#!/bin/bash
# real.sh: the real frame (tests/data/0006_30-deg-right_00043.png), both cars given as boxes, list=true: the found objects' fitted poses, base and new
for side in base new; do
T=/tmp/s9data/fogflip/$side; OUT=/tmp/s9data/fogflip/real/$side; mkdir -p $OUT
cat > $OUT/spec.yaml <<EOS
objects:
- {box: [466, 203, 666, 333], class: Car}
- {box: [704, 194, 917, 305], class: Car}
EOS
cd $T && PYTHONPATH=$T/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit input.image=/work/main/tests/data/0006_30-deg-right_00043.png run=/tmp/s5data/lead/demo/runs proposals=boxes edits=$OUT/spec.yaml list=true output_dir=$OUT/out > $OUT/log.txt 2>&1
echo "$side rc=$?"
done
