#!/bin/bash
# final.sh: the final measurements of rotcost, one job after the other (a shared, loaded 2-core machine)
W=/work/wt/s9-rotcost; R=$W/docs/results/2026-11-29_cpu/session9/rotcost; D=/tmp/s9data/rotcost; C=/tmp/s8data/photocost/t1cap
PY="env OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
cd $W; git log --oneline -1
echo "== lat3 identity"; $R/ident.sh > $D/identity_lat3.txt 2>&1; cat $D/identity_lat3.txt
echo "== t1_31 identity (session 8's captured render_photo calls; main's replay: rep_main_t1)"
rm -rf $D/rep_new_t1; (cd /tmp && PYTHONPATH=$W/src:$W $PY $R/replay_photo.py $D/rep_new_t1 --cap $C/gt_derender $C/semantic_derender $C/gt_oracle > $D/rep_new_t1.log 2>&1)
$PY $R/replay_photo.py --compare $D/rep_main_t1 $D/rep_new_t1 > $D/identity_t1_31.txt 2>&1; cat $D/identity_t1_31.txt
for run in 1 2 3; do
  echo "== side by side, fresh, run $run"; uptime
  PYTHONPATH=$W/src:$W $PY benchmarks/photo_latency.py --data /tmp/s5data/deletes/lat3 --fills rays --threads 1 --against main=$D/src_main > $D/lat_final_run$run.txt 2>&1
  uptime >> $D/lat_final_run$run.txt; tail -12 $D/lat_final_run$run.txt
done
echo "== top costs (CPU-timed cProfile)"
PYTHONPATH=$W/src:$W $PY $R/top_costs.py /tmp/s5data/deletes/lat3 $D/top_costs_this.md "this branch" > /dev/null 2>&1
PYTHONPATH=$D/src_main:$W $PY $R/top_costs.py /tmp/s5data/deletes/lat3 $D/top_costs_main.md "main a03af56" > /dev/null 2>&1
cat $D/top_costs_this.md $D/top_costs_main.md
echo "== all done"; uptime
