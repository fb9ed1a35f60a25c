#!/bin/bash
# held.sh: the held-out seeds 2157 and 2159, once, after the code was final (branch e126cb4): generate each Table 1 tree
# (session 9 fogflip's gen_t1.py), then main (/tmp/s17data/lead/base_35b) and the branch (/tmp/s17data/semfit/code_b)
# on the semantic-proposal row of both seeds, then main's ground-truth-mask (oracle) row of both and the branch's
# ground-truth-mask de-renders checked identical to main's (gtcheck.py).
S=$(cd "$(dirname "$0")" && pwd); D=/tmp/s17data/semfit; M=/tmp/s17data/lead/base_35b; B=$D/code_b
PY=/work/main/.venv/bin/python; G=/work/main/docs/results/2026-11-29_cpu/session9/fogflip/scripts/gen_t1.py
for seed in 2157 2159; do
  (cd $M && PYTHONPATH=$M/src:$M OMP_NUM_THREADS=1 nice -n 5 $PY $G $D/t1_$seed $seed > $D/gen$seed.log 2>&1)
  echo "generated $seed rc=$? $(date +%T)"
done
for seed in 2157 2159; do
  "$S/run.sh" $M m${seed}_semantic $D/t1_$seed semantic $D/cache_m$seed
  "$S/run.sh" $B b${seed}_semantic $D/t1_$seed semantic $D/cache_b$seed
done
for seed in 2157 2159; do "$S/run.sh" $M m${seed}_gt $D/t1_$seed gt $D/cache_m$seed; done
for seed in 2157 2159; do
  (cd $B && PYTHONPATH=$B/src:$B OMP_NUM_THREADS=1 nice -n 5 $PY "$S/gtcheck.py" $D/t1_$seed $D/cache_m$seed 100)
done
echo "held done $(date +%T)"
