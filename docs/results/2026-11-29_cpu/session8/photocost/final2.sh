#!/bin/bash
W=/work/wt/s8-photocost; R=$W/docs/results/2026-11-29_cpu/session8/photocost; D=/tmp/s8data/photocost
cd $W
echo "== this replay t1 (3 sources)"; rm -rf $D/rep_new_t1; PYTHONPATH=$W/src:$W OMP_NUM_THREADS=1 /work/main/.venv/bin/python $R/replay_photo.py $D/rep_new_t1 --cap $D/t1cap/gt_derender $D/t1cap/semantic_derender $D/t1cap/gt_oracle > $D/rep_new_t1.log 2>&1
/work/main/.venv/bin/python $R/replay_photo.py --compare $D/rep_main_t1 $D/rep_new_t1 > $D/identity_t1_31.txt 2>&1; cat $D/identity_t1_31.txt
echo "== lat3 identity"; /tmp/s8data/photocost/ident.sh > $D/identity_lat3.txt 2>&1; cat $D/identity_lat3.txt
echo "== side by side, fresh, run 3"; PYTHONPATH=$W/src:$W OMP_NUM_THREADS=1 /work/main/.venv/bin/python benchmarks/photo_latency.py --data /tmp/s5data/deletes/lat3 --fills rays --threads 1 --against main=$D/src_main > $D/lat_final_fresh3.txt 2>&1; tail -11 $D/lat_final_fresh3.txt
echo "== side by side, reuse, run 2"; PYTHONPATH=$W/src:$W OMP_NUM_THREADS=1 /work/main/.venv/bin/python benchmarks/photo_latency.py --data /tmp/s5data/deletes/lat3 --fills rays --threads 1 --reuse-source --against main=$D/src_main > $D/lat_final_reuse2.txt 2>&1; tail -11 $D/lat_final_reuse2.txt
echo "== all done"
