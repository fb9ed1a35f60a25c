#!/bin/bash
# offer_f.sh: NOT on this branch. Code F = the final code (E, /tmp/s9data/rot05/code_E) with _coherence's 7x7 window
# sums by cv2.boxFilter (zero border) instead of F.avg_pool2d (the vote's, the lead's area; offer_coherence_boxfilter.patch
# without its docstring change): its replays against E, cf31 and Table 1 oracle runs, and 2 side-by-side latency runs
# against main (the benchmark copied into code_F/benchmarks, so that its "this" code is F), for the lead to decide
R=/work/wt/s9-rot05/docs/results/2026-11-29_cpu/session9/rot05; D=/tmp/s9data/rot05; C=/tmp/s8data/photocost/t1cap
( cd $D && PYTHONPATH=$D/code_F/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python $R/replay_photo.py rep_F --lat /tmp/s5data/deletes/lat3 --cap $C/gt_derender $C/semantic_derender $C/gt_oracle > rep_F.log 2>&1
  /work/main/.venv/bin/python $R/replay_photo.py --compare rep_E rep_F > $D/cmp_E_F.txt 2>&1; bash $R/cf.sh $D/code_F $D/cf31_F ) &
( bash $R/t1.sh $D/code_F $D/t1_F
  mkdir -p $D/code_F/benchmarks && cp /work/wt/s9-rot05/benchmarks/photo_latency.py $D/code_F/benchmarks/
  cd $D/code_F && for run in 1 2; do PYTHONPATH=$D/code_F/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python $D/code_F/benchmarks/photo_latency.py --data /tmp/s5data/deletes/lat3 --fills rays --threads 1 --against main=$D/main_code/src --json $D/latF_run$run.json > $D/latF_run$run.txt 2>&1; done
  /work/main/.venv/bin/python $R/paired.py $D/latF.md $D/latF_run*.json ) &
wait; echo "F done"
