#!/bin/bash
# heldout2273.sh MAIN BRANCH WEIGHTS: held-out seed 2273 (README's merge rule, session 28 amendment): generate the
# counterfactual tree with main's generator (gen_cf.py: worlds 0006/0018/0020, 6 cars), then the delete bench (fill
# rays) of the plain code trees MAIN and BRANCH, predicted (semantic, the demo weights under WEIGHTS/runs) and
# ground-truth geometry (oracle), two at a time, one thread each, nice 5; outputs /tmp/s28/shadow41/{main,branch}2273_<source>/.
MAIN=$1; BR=$2; W=$3; D=$(cd "$(dirname "$0")" && pwd); H=/tmp/s28/shadow41; T=$H/trees/cf2273
PY=/work/main/.venv/bin/python
mkdir -p $H/trees
[ -f $T/DONE ] || { (cd $MAIN && PYTHONPATH=$MAIN/src OMP_NUM_THREADS=1 nice -n 5 $PY "$D/gen_cf.py" $T 2273 \
  0006,0018,0020 6 > $H/gen.log 2>&1) && touch $T/DONE; }
echo "gen done $(date -u +%T)"
bench() {  # bench SRC OUT SOURCE
  local CK=""
  [ "$3" = semantic ] && CK="checkpoints.semantic=$W/runs/semantic/checkpoints/inference.pt checkpoints.geometric=$W/runs/geometric/checkpoints/inference.pt"
  (cd "$1" && PYTHONPATH=$1/src OMP_NUM_THREADS=1 nice -n 5 $PY -m sdn3d.cli.bench counterfactual=true \
    data.root="$T" output_dir="$2" examples=0 threads=1 "counterfactual_kinds=[delete]" "counterfactual_sources=[$3]" \
    "counterfactual_fills=[rays]" $CK > "$2.log" 2>&1); echo "$2 rc=$? $(date -u +%T)"
}
for SRC in semantic oracle; do
  bench $MAIN $H/main2273_$SRC $SRC &
  bench $BR $H/branch2273_$SRC $SRC
  wait
done
