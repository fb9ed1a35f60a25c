#!/bin/bash
# counterfactual deletes with CODE's defaults (gated), signals logged
CODE=${CODE:-/work/wt/s7-haze}; tag=${TAG:-gated}
cd $CODE
for t in cf37 cf39 cf33; do
  r=/tmp/s7data/haze/$t; [ $t = cf33 ] && r=/tmp/s3data/cf33
  PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s7data/haze/cf_diag.py $r /tmp/s7data/haze/${t}_${tag}.json $tag $tag "$@" > /tmp/s7data/haze/${t}_${tag}.log 2>&1
  echo done $t
done
