#!/bin/bash
# held_report.sh: the held-out tables (held.sh's runs): semantic proposals, main against the branch (gap.py), pooled
# over 2157 + 2159 and per seed; ground-truth masks (oracle), main's 3D-SDN minus 2D (session 13's paired.py; the
# branch's de-renders of that row are main's, gtcheck.py), pooled and per seed.
S=$(cd "$(dirname "$0")" && pwd); R=/tmp/s17data/semfit/runs; PY=/work/main/.venv/bin/python
P=/work/main/docs/results/2026-11-29_cpu/session13/rotloss/scripts/paired.py
$PY "$S/gap.py" "held-out 2157+2159 semantic proposals" $R/m2157_semantic:$R/b2157_semantic $R/m2159_semantic:$R/b2159_semantic
for s in 2157 2159; do $PY "$S/gap.py" "held-out $s semantic proposals" $R/m${s}_semantic:$R/b${s}_semantic; done
if [ -f $R/m2157_gt/results.json ] && [ -f $R/m2159_gt/results.json ]; then
  $PY $P "held-out 2157+2159 ground-truth masks (oracle), main (new = base: the same run)" $R/m2157_gt:$R/m2157_gt $R/m2159_gt:$R/m2159_gt | grep -v "^clone\|^rain"
fi
for s in 2157 2159; do [ -f $R/m${s}_gt/results.json ] && $PY $P "held-out $s ground-truth masks (oracle), main" $R/m${s}_gt:$R/m${s}_gt | grep -E "^==|^--|^ALL   ALL"; done
