#!/bin/bash
# tune.sh CODE_DIR NAME [OVERRIDES...]: counterfactual turns (photo appearance, fill rays, ground-truth geometry
# (oracle)) on the tuning trees cf31 and cf33 with the code at CODE_DIR (a git archive or snapshot); outputs under
# /tmp/s17data/glass/tune/{cf31,cf33}_oracle_NAME.
set -u
S=$1; N=$2; shift 2; O=/tmp/s17data/glass/tune; mkdir -p $O
declare -A TREES=([cf31]=/tmp/s11data/lead/cf31 [cf33]=/tmp/s14data/ends/cf33)
for T in cf31 cf33; do
  (cd "$S" && PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench \
    counterfactual=true data.root=${TREES[$T]} output_dir=$O/${T}_oracle_$N examples=0 threads=1 \
    'counterfactual_fills=[rays]' 'counterfactual_kinds=[turn]' 'counterfactual_sources=[oracle]' "$@" \
    > $O/${T}_oracle_$N.log 2>&1)
  echo "$T $N rc=$? $(date -u +%T)" >> $O/tune.log
done
