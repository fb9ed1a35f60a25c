cd /work/wt/s5-cost
R=/tmp/s5data/cost/val13; mkdir -p $R
name=$1; shift
uptime >> $R/sweep2_$name.log
env "$@" PYTHONPATH=/work/wt/s5-cost/src OMP_NUM_THREADS=1 STRIDE=2 /work/main/.venv/bin/python /tmp/s5data/cost/evalfit.py /tmp/s4data/cost/val13_capture.pt $R/$name.json $ARGS >> $R/sweep2_$name.log 2>&1
echo "$name done $(uptime)" >> $R/sweep2_$name.log
