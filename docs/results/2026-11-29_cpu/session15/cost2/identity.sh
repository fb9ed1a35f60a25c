#!/bin/bash
# identity.sh: this branch's outputs against main's (NEW, BASE: git archives of the two commits), written under OUT:
# the 14 latency edits (session14/cost/draw_edits.py, a fresh source per edit and one source per frame), cf31's
# counterfactual pairs (oracle geometry, fill rays) and the real strip (session4/poses/real_strip.py); each
# compared by same_outputs.py into OUT/identity.log.
set -u
NEW=$1; BASE=$2; O=$3; mkdir -p $O
R=$(cd "$(dirname "$0")" && pwd); PY="nice -n 5 /work/main/.venv/bin/python"; export OMP_NUM_THREADS=1
DRAW=$NEW/docs/results/2026-11-29_cpu/session14/cost/draw_edits.py; TREE=/tmp/s14data/cost/vkitti
for C in new:$NEW base:$BASE; do S=${C#*:}; N=${C%%:*}
  PYTHONPATH=$S/src $PY $DRAW $TREE $O/edits_$N > $O/edits_$N.txt 2>&1
  PYTHONPATH=$S/src $PY $DRAW $TREE $O/reuse_$N --reuse-source > $O/reuse_$N.txt 2>&1
  (cd $S && PYTHONPATH=$S/src $PY -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s11data/lead/cf31 \
    output_dir=$O/cf31/$N examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_sources=[oracle]' \
    overwrite=true > $O/cf31_$N.log 2>&1)
  (cd $S && PYTHONPATH=$S/src SDN3D_CONFIG_DIR=$S/conf $PY $S/docs/results/2026-11-28_cpu/session4/poses/real_strip.py \
    /tmp/s11data/demo/out/runs $O/strip/$N threads=1 > $O/strip_$N.log 2>&1)
done
{ uptime
  echo "14 latency edits, a fresh source per edit:"; $PY $R/same_outputs.py $O/edits_new.npz $O/edits_base.npz
  echo "14 latency edits, one source per frame (--reuse-source):"; $PY $R/same_outputs.py $O/reuse_new.npz $O/reuse_base.npz
  echo "cf31 counterfactual pairs:"; $PY $R/same_outputs.py $O/cf31/new $O/cf31/base
  echo "real strip:"; $PY $R/same_outputs.py $O/strip/new $O/strip/base; } > $O/identity.log 2>&1
