#!/bin/bash
cd /tmp/s28/merge40
for s in "$@"; do
  PYTHONPATH=/tmp/s28/merge40/base/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python gen_t1.py trees/t1_$s $s > gen$s.log 2>&1
  ./dc.sh /tmp/s28/merge40/base main $s
done
