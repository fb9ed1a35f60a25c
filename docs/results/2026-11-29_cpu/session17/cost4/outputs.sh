#!/bin/bash
# outputs.sh NAME SRC OUT: one code's outputs for the byte-identity checks (SRC: a git archive of the code), under
# OUT/NAME: the 14 latency edits (session14/cost/draw_edits.py: a fresh source per edit, and one per frame), cf31's
# counterfactual pairs (ground-truth geometry (oracle), fill rays, 180 pairs) and the real strip (session15/sides/real.sh).
# compare.sh then compares two codes' outputs with session15/cost2/same_outputs.py.
set -u
N=$1; S=$2; O=$3; mkdir -p $O/$N
R=$(cd "$(dirname "$0")/../.." && pwd); PY="nice -n 5 /work/main/.venv/bin/python"; export OMP_NUM_THREADS=1
DRAW=$R/session14/cost/draw_edits.py; TREE=/tmp/s14data/cost/vkitti
echo "$N start $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/outputs.log
PYTHONPATH=$S/src $PY $DRAW $TREE $O/$N/edits > $O/$N/edits.txt 2>&1
PYTHONPATH=$S/src $PY $DRAW $TREE $O/$N/reuse --reuse-source > $O/$N/reuse.txt 2>&1
(cd $S && PYTHONPATH=$S/src $PY -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s11data/lead/cf31 \
  output_dir=$O/$N/cf31 examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_sources=[oracle]' \
  overwrite=true > $O/$N/cf31.log 2>&1)
bash $R/session15/sides/real.sh $N:$S $O/$N/real
echo "$N end $(date -u +%T) load $(cut -d' ' -f1-3 /proc/loadavg)" >> $O/outputs.log
