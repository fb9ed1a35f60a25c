#!/bin/bash
# lowload.sh N: paired.sh, run again when the load dropped: N side-by-side runs of lat3 (this worktree against main a03af56), each edit's times kept as JSON,
# then paired.py's table over them
W=/work/wt/s9-rotcost; R=$W/docs/results/2026-11-29_cpu/session9/rotcost; D=/tmp/s9data/rotcost
cd $W
for run in $(seq 1 "${1:-4}"); do
  echo "== paired run $run"; uptime
  PYTHONPATH=$W/src:$W OMP_NUM_THREADS=1 /work/main/.venv/bin/python benchmarks/photo_latency.py --data /tmp/s5data/deletes/lat3 --fills rays --threads 1 --against main=$D/src_main --json $D/lowload_run$run.json > $D/lowload_run$run.txt 2>&1
  uptime >> $D/lowload_run$run.txt; tail -13 $D/lowload_run$run.txt
done
/work/main/.venv/bin/python $R/paired.py $D/lowload.md $D/lowload_run*.json
