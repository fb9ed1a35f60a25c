#!/bin/bash
# held.sh: held-out seed 2171 (counterfactual tree, session 5's recipe), generated after the code was final (6d1ee02),
# measured once: main (d47d803, /tmp/s19data/lead/base_d47) against the branch (/tmp/s19data/erase/br_6d1, a git
# archive of 6d1ee02): deletes with ground-truth geometry (oracle; main's also Telea and PatchMatch), turns (rays).
# Then the predicted deletes (the session 11 demo's weights). Threads 1, nice 5; outputs under /tmp/s19data/erase/held.
B=/work/wt/erase/docs/results/2026-11-30_cpu/session19/erase/bench.sh
M=/tmp/s19data/lead/base_d47; R=/tmp/s19data/erase/br_6d1; O=/tmp/s19data/erase/held; T=/tmp/s19data/erase/cf2171
mkdir -p $O
cd /work/wt/erase && PYTHONPATH=$M/src OMP_NUM_THREADS=1 nice -n 5 /work/main/.venv/bin/python \
  docs/results/2026-11-28_cpu/session5/turns/gen_cf.py $T 2171 0006,0018,0020 6 > $O/gen.log 2>&1
echo "gen rc=$?"
$B $M $T $O/m_oracle oracle '[telea,patchmatch,rays,learnt]' '[delete]'
$B $R $T $O/b_oracle oracle '[rays,learnt]' '[delete]'
$B $M $T $O/m_turn oracle '[rays]' '[turn]'
$B $R $T $O/b_turn oracle '[rays]' '[turn]'
