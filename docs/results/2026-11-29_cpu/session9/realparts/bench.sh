#!/bin/bash
# (session 9 realparts record; /tmp/s9data/realparts is the work dir)
# bench.sh CODE TREE OUT : turn kind of the counterfactual benchmark (ground-truth geometry oracle and predicted)
code=$1; tree=$2; out=$3
cd $code && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$tree output_dir=$out 'counterfactual_fills=[auto]' 'counterfactual_kinds=[turn]' examples=0 > $out.log 2>&1
echo rc=$? >> $out.log
