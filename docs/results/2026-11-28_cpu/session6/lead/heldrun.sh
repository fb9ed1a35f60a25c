#!/bin/bash
# heldrun.sh CODE_DIR TAG TREE : Table 1 photo rows (gt derender, semantic derender, gt oracle) with the session-5 demo's weights
code=$1; tag=$2; tree=$3; out=/tmp/s6data/lead/held; mkdir -p $out
for sc in "gt derender" "semantic derender" "gt oracle"; do set -- $sc
cd $code && PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 nice -n 3 /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=$tree 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' "proposals=[$1]" scene=$2 threads=1 examples=4 output_dir=$out/${tag}_$1_$2 > $out/${tag}_$1_$2.log 2>&1
echo "done ${tag}_$1_$2 rc=$?"
done
