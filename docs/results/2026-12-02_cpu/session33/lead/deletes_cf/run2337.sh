#!/bin/bash
# run2337.sh: held-out counterfactual deletes 2337 (generated once: refuses if the tree exists), scored for the three
# source scenes with the default fill (rays); the 2D paste is scored beside as always. Code: a plain tree of main
# (CODE), weights w33. Outputs under /tmp/s33/cf2337/.
set -u
B=/tmp/s33/cf2337; CODE=$B/base; W=/tmp/s33/democlone/outputs/demo; TREE=$B/t2337; PY=/work/main/.venv/bin/python
GEN=/work/main/docs/results/2026-12-01_cpu/session31/lead/cfdel2303/gen_cf.py
[ -e "$TREE" ] && { echo "tree $TREE exists: one generation only" >&2; exit 3; }
export PYTHONPATH=$CODE/src OMP_NUM_THREADS=1
echo "gen start $(date -u +%T)" >> $B/log.txt
nice -n 5 $PY $GEN $TREE 2337 0001,0002,0006,0018,0020,0003,0004,0005 8 > $B/gen.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> $B/log.txt
cd $CODE && SDN3D_CONFIG_DIR=$CODE/conf nice -n 5 $PY -m sdn3d.cli.bench counterfactual=true data.root=$TREE run=$W \
  'counterfactual_kinds=[delete]' 'counterfactual_sources=[oracle,gt,semantic]' 'counterfactual_fills=[rays]' \
  threads=1 output_dir=$B/out > $B/bench.log 2>&1
echo "bench rc=$? $(date -u +%T)" >> $B/log.txt
