#!/bin/bash
# ident.sh [replay args]: lat3's 14 edits replayed with this worktree's code, compared with main's (rep_main, made by
# replay_photo.py with main's code, git archive a03af56, on PYTHONPATH)
W=/work/wt/s9-rotcost; R=$W/docs/results/2026-11-29_cpu/session9/rotcost; D=/tmp/s9data/rotcost
cd $W && rm -rf $D/rep_new && PYTHONPATH=$W/src:$W OMP_NUM_THREADS=1 /work/main/.venv/bin/python $R/replay_photo.py $D/rep_new --lat /tmp/s5data/deletes/lat3 "$@" 2>&1 | tail -14 | awk '{printf "%s %s | ", $1, $2}'; echo
/work/main/.venv/bin/python $R/replay_photo.py --compare $D/rep_main $D/rep_new
