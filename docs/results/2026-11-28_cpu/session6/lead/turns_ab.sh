#!/bin/bash
# turns_ab.sh: oracle turn bins on tuning trees cf33, cf31: baseline (HEAD worktree) vs main working tree
for tree in /tmp/s3data/cf33 /tmp/s5data/turns/cf31; do
  t=$(basename $tree)
  for v in base:/work/wt/lead-base new:/tmp/s6data/lead/code_new; do
    name=${v%%:*}; code=${v#*:}
    bash /work/main/docs/results/2026-11-28_cpu/session5/turns/bench.sh $code $tree /tmp/s6data/lead/tt_${t}_$name 'examples=0'
  done
done
