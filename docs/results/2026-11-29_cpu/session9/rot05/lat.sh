#!/bin/bash
# lat.sh TAG N: N side-by-side runs of benchmarks/photo_latency.py on lat3 (fill rays, 1 thread; this worktree's code
# against main fc689d8 = git archive in /tmp/s9data/rot05/main_code/src, the two codes taking turns edit by edit),
# each edit's times kept as JSON, then paired.py's table over them
W=/work/wt/s9-rot05; R=$W/docs/results/2026-11-29_cpu/session9/rot05; D=/tmp/s9data/rot05
cd $W
for run in $(seq 1 "${2:-3}"); do
  echo "== $1 run $run"; uptime
  PYTHONPATH=$W/src:$W OMP_NUM_THREADS=1 /work/main/.venv/bin/python benchmarks/photo_latency.py --data /tmp/s5data/deletes/lat3 --fills rays --threads 1 --against main=$D/main_code/src --json $D/$1_run$run.json > $D/$1_run$run.txt 2>&1
  uptime >> $D/$1_run$run.txt; tail -8 $D/$1_run$run.txt
done
/work/main/.venv/bin/python $R/paired.py $D/$1.md $D/$1_run*.json
