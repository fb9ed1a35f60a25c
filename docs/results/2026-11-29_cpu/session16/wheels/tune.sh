#!/bin/bash
# tune.sh CODE_DIR NAME: sdn3d-bench counterfactual turns (photo fill rays, ground-truth geometry (oracle)) on the
# tuning trees cf31 and cf33, code CODE_DIR (a git archive or snapshot), outputs under /tmp/s16data/wheels/tune.
S=$1; N=$2; shift 2; O=/tmp/s16data/wheels/tune; mkdir -p $O
for T in cf31 cf33; do [ $T = cf31 ] && TREE=/tmp/s11data/lead/cf31 || TREE=/tmp/s14data/ends/cf33
  (cd $S && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$TREE output_dir=$O/${T}_oracle_$N examples=0 threads=1 'counterfactual_fills=[rays]' 'counterfactual_kinds=[turn]' "counterfactual_sources=[oracle]" "$@" > $O/${T}_oracle_$N.log 2>&1)
  echo "$T $N rc=$? $(date -u +%T)" >> $O/tune.log
done
