#!/bin/bash
# run.sh CODE NAME TREE SOURCE(gt|semantic) CACHE [ARGS...]: one Table 1 photo row (session 11's demo weights, 312x96,
# fit_proposals on, per-entry npz dumped) by session 11 semrain's dbench.py, into /tmp/s17data/semfit/runs/NAME.
code=$1; name=$2; tree=$3; p=$4; cache=$5; shift 5
o=/tmp/s17data/semfit/runs/$name; mkdir -p "$(dirname "$o")"
DB=/work/main/docs/results/2026-11-29_cpu/session11/semrain/scripts/dbench.py
cd "$code" && PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $DB "$cache" "$o.dump" \
  data.root="$tree" 'data.image_size=[312,96]' run=/tmp/s11data/demo/out 'compose=[photo]' "proposals=[$p]" \
  scene=derender threads=1 examples=0 output_dir="$o" "$@" > "$o.log" 2>&1
echo "done $name rc=$? $(date +%T)"
