#!/bin/bash
# run.sh CODE NAME TREE SOURCE(gt|semantic) SCENE(derender|oracle) CACHE EXAMPLES [ARGS...]: one Table 1 photo row with cached de-renders
code=$1; name=$2; tree=$3; p=$4; sc=$5; cache=$6; ex=$7; shift 7
D=/tmp/s10data/semflip/runs; mkdir -p $D
o=$D/${name}
cd $code && PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s10data/semflip/cbench.py $cache $o.picks.json data.root=$tree 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' "proposals=[$p]" scene=$sc threads=1 examples=$ex output_dir=$o "$@" > $o.log 2>&1
echo "done $name rc=$?"
