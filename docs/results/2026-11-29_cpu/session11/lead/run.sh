#!/bin/bash
# run.sh NAME TREE SOURCE(gt|semantic) SCENE(derender|oracle) CACHE [ARGS...]: one Table 1 photo row (main's work tree,
# de-renders cached per tree and source), the demo weights of /tmp/s11data/demo/out/runs
name=$1; tree=$2; p=$3; sc=$4; cache=$5; shift 5
D=/tmp/s11data/lead/runs; o=$D/$name
cd /work/main && PYTHONPATH=/work/main/src:/work/main OMP_NUM_THREADS=1 nice -n 5 .venv/bin/python /tmp/s11data/lead/scripts/cbench.py $cache $o.picks.json data.root=$tree 'data.image_size=[312,96]' run=/tmp/s11data/demo/out/runs 'compose=[photo]' "proposals=[$p]" scene=$sc threads=1 examples=0 output_dir=$o "$@" > $o.log 2>&1
echo "done $name rc=$?"
