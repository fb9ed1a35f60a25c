#!/bin/bash
# held.sh CODE: held-out Table 1 seed 2143, generated after the branch's code was final (session 9 fogflip's gen_t1.py,
# the tuning trees' recipe, run by main's code), measured once: main (9f19738) and the branch (CODE, a git archive of
# its final commit), both rows (semantic proposals; ground-truth masks (oracle)), session 11's demo weights.
S=$(cd "$(dirname "$0")" && pwd); B=/tmp/s16data/lead/base_9f1; C=/tmp/s16data/picks; code=$1
G=/work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py
cd $B && PYTHONPATH=$B/src:$B OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python $G $C/t1_2143 2143 > $C/gen2143.log 2>&1
echo "generated rc=$? $(date +%T)"
for p in semantic gt; do
  $S/run.sh $B h2143m_$p $C/t1_2143 $p $C/cache_h2143m
  $S/run.sh $code h2143b_$p $C/t1_2143 $p $C/cache_h2143b
done
echo held done
