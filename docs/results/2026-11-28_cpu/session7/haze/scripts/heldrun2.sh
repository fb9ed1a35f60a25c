#!/bin/bash
# heldrun.sh SOURCE SCENE WORLD : held-out Table 1 (seed 2083) photo rows for one source scene and one world (shard;
# SHARD_WORLD: the other world's entries are skipped) with three codes: start (f45beb0, /work/main, read-only) first,
# then final (src_final = dc1e333) and final with photo.ray_haze=0 side by side; session-5 demo weights, 312x96,
# de-rendered source scenes cached on disk (the same de-render code and weights for all three); the 2D / 2D+ rows
# are not drawn (SKIP2D: their pictures are the source), only 3D-SDN's are compared
p=$1; sc=$2; w=$3; wn=${4:-$3}; tree=/tmp/s7data/haze/t1_2083; D=/tmp/s7data/haze/held; mkdir -p $D
export SKIP2D=1 SHARD_WORLD=$w
run() { code=$1; tag=$2; shift 2
  cd $code && PYTHONDONTWRITEBYTECODE=1 PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s7data/haze/cbench.py /tmp/s7data/haze/cache_t1_2083_${p}_${sc} $D/t1_2083_${tag}_${p}_${sc}_$wn.sig.json data.root=$tree 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' "proposals=[$p]" scene=$sc threads=1 examples=0 output_dir=$D/t1_2083_${tag}_${p}_${sc}_$wn "$@" > $D/t1_2083_${tag}_${p}_${sc}_$wn.log 2>&1
  echo "done ${tag}_${p}_${sc}_$wn rc=$?"; }
run /work/main start
run /tmp/s7data/haze/src_final final &
run /tmp/s7data/haze/src_final final0 +photo.ray_haze=0 &
wait
