#!/bin/bash
# final2.sh: the final measurements again on the final code (after _part_examples went back to main's), one job after
# the other: identity (lat3, t1_31), 4 paired side-by-side runs, the two codes' CPU profiles at the same time
W=/work/wt/s9-rotcost; R=$W/docs/results/2026-11-29_cpu/session9/rotcost; D=/tmp/s9data/rotcost; C=/tmp/s8data/photocost/t1cap
PY="env OMP_NUM_THREADS=1 /work/main/.venv/bin/python"
cd $W; git log --oneline -1
echo "== lat3 identity"; $R/ident.sh > $D/identity_lat3.txt 2>&1; cat $D/identity_lat3.txt
echo "== t1_31 identity"
rm -rf $D/rep_new_t1; (cd /tmp && PYTHONPATH=$W/src:$W $PY $R/replay_photo.py $D/rep_new_t1 --cap $C/gt_derender $C/semantic_derender $C/gt_oracle > $D/rep_new_t1.log 2>&1)
$PY $R/replay_photo.py --compare $D/rep_main_t1 $D/rep_new_t1 > $D/identity_t1_31.txt 2>&1; cat $D/identity_t1_31.txt
rm -f $D/paired_run*.json $D/paired_run*.txt; $R/paired.sh 4
echo "== top costs, both codes at the same time (CPU-timed cProfile)"
PYTHONPATH=$W/src:$W $PY $R/top_costs.py /tmp/s5data/deletes/lat3 $D/top_costs_this.md "this branch" > /dev/null 2>&1 &
PYTHONPATH=$D/src_main:$W $PY $R/top_costs.py /tmp/s5data/deletes/lat3 $D/top_costs_main.md "main a03af56" > /dev/null 2>&1
wait
cat $D/top_costs_this.md $D/top_costs_main.md
echo "== all done"; uptime
