#!/bin/bash
# (session 9 realparts record; /tmp/s9data/realparts is the work dir)
# benchvar.sh VARIANT TREE OUT
var=$1; tree=$2; out=$3
cd /tmp/s9data/realparts/new_tree && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s9data/realparts/runvar.py "$var" counterfactual=true data.root=$tree output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn]' examples=0 > $out.log 2>&1
echo rc=$? >> $out.log
