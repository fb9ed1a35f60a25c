# ruff: noqa: INP001, E501
# abin.sh ROUNDS N OUT SPEC...: bench.py (N in-process photo stages per captured spec, its median) with the base
# worktree (/work/wt_photo_base) and with /work/wt_photo (or $NEW), alternated within each round (the order flipped every other
# round); lines: round, spec, base or new, least CPU ms, median wall ms, picture hash (abt.py reads the first four)
cd /work/wt_photo
rounds=$1 n=$2 out=$3
shift 3
new=${NEW:-/work/wt_photo/src}  # the code under test (a snapshot of it, while the tree changes)
for r in $(seq 1 $rounds); do
  [ $((r % 2)) = 1 ] && order="base new" || order="new base"
  for v in $order; do
    [ $v = base ] && pp=/work/wt_photo_base/src || pp=$new
    PYTHONPATH=$pp OMP_NUM_THREADS=1 /work/main/.venv/bin/python docs/results/2026-12-02_cpu/session38/perf/bench.py $n "$@" |
      while read -r spec _ _ _ median _ _ _ _ cpu hash; do echo "$r ${spec%:} $v $cpu $median $hash"; done >> $out
  done
done
