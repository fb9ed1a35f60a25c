#!/bin/bash
# t1run.sh TREE NAME SOURCE(gt|semantic) SCENE(derender|oracle) ARGS... : Table 1 photo rows, cached de-render, session-5 demo weights, 312x96
tree=$1; name=$2; p=$3; sc=$4; shift 4
W=${CODE:-/tmp/s7data/haze/src_start}; D=/tmp/s7data/haze/runs; mkdir -p $D
tn=$(basename $tree)
cd $W && PYTHONPATH=$W/src:$W OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s7data/haze/cbench.py /tmp/s7data/haze/cache_${tn}_$p_$sc $D/${tn}_${name}_${p}_${sc}.sig.json data.root=$tree 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' "proposals=[$p]" scene=$sc threads=1 examples=0 output_dir=$D/${tn}_${name}_${p}_${sc} "$@" > $D/${tn}_${name}_${p}_${sc}.log 2>&1
echo "done ${tn}_${name}_${p}_${sc} rc=$?"
