#!/bin/bash
# the held-out seed 2065, measured once: issue-time (6c4cf46) and main (774bffb); the final code (c2f693c, default and
# photo.outline_grow=0.1) ran as: bench.sh CODE_FINAL cf2065 OUT [photo.outline_grow=0.1], and with
# run=/work/final_demo/runs 'counterfactual_sources=[gt]' limit=9 for the predicted-geometry rows
T=/tmp/s5data/turns; H=$T/cf2065
while [ ! -f $H/_SUCCESS ]; do sleep 10; done
echo "tree ready $(date +%T)"
(cd $T/issue_time && PYTHONPATH=$PWD/src:$PWD OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=$H output_dir=$T/h2065_issue 'counterfactual_fills=[auto]' > $T/h2065_issue.log 2>&1; echo "issue done rc=$? $(date +%T)") &
$T/bench.sh $T/main_code $H $T/h2065_main &
# final: run separately
wait
echo "oracle done $(date +%T)"
wait
echo "gt done $(date +%T)"
