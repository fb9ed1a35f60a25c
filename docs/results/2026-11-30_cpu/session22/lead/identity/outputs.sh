#!/bin/bash
# outputs.sh NAME SRC OUT: one code's outputs for the byte-identity checks (SRC: a copy of the code), under OUT/NAME
# (session 17 cost4's outputs.sh with session 22's paths): the 14 latency edits (session14/cost/draw_edits.py: a
# fresh source per edit, and one per frame), cf31's counterfactual pairs (ground-truth geometry (oracle), fill rays)
# and the real frame's edits in one EditSession (session15/sides/real.sh's probe), session 21's demo weights (w0).
# compare.sh then compares two codes' outputs with session15/cost2/same_outputs.py.
set -u
N=$1; S=$2; O=$3; mkdir -p $O/$N
R=$(cd "$(dirname "$0")/../../../.." && pwd); PY="nice -n 5 /work/main/.venv/bin/python"; export OMP_NUM_THREADS=1
DRAW=$R/2026-11-29_cpu/session14/cost/draw_edits.py; TREE=/tmp/s22data/lead/latency_tree
echo "$N start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/outputs.log
PYTHONPATH=$S/src $PY $DRAW $TREE $O/$N/edits > $O/$N/edits.txt 2>&1
PYTHONPATH=$S/src $PY $DRAW $TREE $O/$N/reuse --reuse-source > $O/$N/reuse.txt 2>&1
(cd $S && PYTHONPATH=$S/src $PY -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s21data/trees/cf31 \
  output_dir=$O/$N/cf31 examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_sources=[oracle]' \
  overwrite=true > $O/$N/cf31.log 2>&1)
(cd $S && PYTHONPATH=$S/src:$S $PY $R/2026-11-29_cpu/session12/realframe/probe.py /tmp/s21data/demo/out/runs \
  $O/$N/real > $O/$N/real.log 2>&1)
echo "$N end $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/outputs.log
