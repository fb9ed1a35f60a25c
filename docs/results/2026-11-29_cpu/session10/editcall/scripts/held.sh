#!/bin/bash
# Held-out seed 2105, generated after the fit code was final: val13's generator (/tmp/s3data/gen_val13.py) with seed
# 2105, then val13's pose-table command on it (oracle: ground-truth masks and ground-truth boxes), before (base f42d17c)
# and after (this branch's final tree), side by side, threads 1.
O=/tmp/s10data/editcall; PY=/work/main/.venv/bin/python; D=$O/val2105; H=$O/held2105; mkdir -p $H
uptime
sed -e 's#/tmp/s3data/val13#'$D'#' -e 's/seed=13/seed=2105/' /tmp/s3data/gen_val13.py > $O/scripts/gen_val2105.py
cd $O/base && PYTHONPATH=$O/base/src OMP_NUM_THREADS=1 $PY $O/scripts/gen_val2105.py > $H/gen.log 2>&1
uptime
TREE=${TREE:-$O/final} O=$H DATA=$D $O/scripts/val13.sh
