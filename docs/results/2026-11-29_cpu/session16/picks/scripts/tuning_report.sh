#!/bin/bash
# tuning_report.sh TAG: main (m*) against the branch (TAG*) on tuning 35/37/31: session 13 rotloss's paired.py per row
# pooled and per seed, the 2D paste check, and picks.py (3D-SDN vs 2D picks) under each code.
S=$(cd "$(dirname "$0")" && pwd); R=/tmp/s16data/picks/runs; C=/tmp/s16data/picks; tag=$1; B=/tmp/s16data/lead/base_9f1
P=/work/main/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py; PY=/work/main/.venv/bin/python
for p in semantic gt; do
  $PY $P "tuning 35+37+31 $p" $R/m35_$p:$R/${tag}35_$p $R/m37_$p:$R/${tag}37_$p $R/m31_$p:$R/${tag}31_$p
  for s in 35 37 31; do $PY $P "tuning $s $p" $R/m${s}_$p:$R/${tag}${s}_$p | grep -E "^==|^--|^ALL   ALL"; done
  $PY $S/baseline_check.py $R/m35_$p:$R/${tag}35_$p $R/m37_$p:$R/${tag}37_$p $R/m31_$p:$R/${tag}31_$p
done
