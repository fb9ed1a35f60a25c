#!/bin/bash
# cap.sh SRC TAG TREE WORLD FRAME IID SOURCE: capture.py (session 19's, speck's copy) on a one-pair copy of TREE (its
# folders linked, counterfactual_pairs.json cut to the delete of car IID in WORLD/clone frame FRAME), source scene
# SOURCE (oracle | semantic: this session's demo weights), fill rays; the drawn pictures into
# /tmp/s21data/island/cap_TAG.pt (read by synthetic_figure.py). Threads 1, nice 5.
S=$1; T=$2; TREE=$3; W=$4; F=$5; I=$6; SRC=$7
ONE=/tmp/s21data/island/one_${T}
rm -rf "$ONE"; mkdir -p "$ONE"
for f in "$TREE"/*; do b=$(basename "$f"); [ "$b" = counterfactual_pairs.json ] || ln -s "$f" "$ONE/$b"; done
/work/main/.venv/bin/python -c "
import json, sys
d = json.load(open('$TREE/counterfactual_pairs.json'))
d['pairs'] = [p for p in d['pairs'] if p['world'] == '$W' and p['variation'] == 'clone' and p['frame'] == $F
              and p['instance_id'] == $I and p['kind'] == 'delete']
json.dump(d, open('$ONE/counterfactual_pairs.json', 'w'))
"
CK=""
[ "$SRC" = semantic ] && CK="checkpoints.semantic=/tmp/s21data/demo/out/runs/semantic/checkpoints/inference.pt checkpoints.geometric=/tmp/s21data/demo/out/runs/geometric/checkpoints/inference.pt"
cd "$S" && CAPTURE=/tmp/s21data/island/cap_$T.pt PYTHONPATH=$S/src OMP_NUM_THREADS=1 nice -n 5 \
  /work/main/.venv/bin/python /work/wt/island/docs/results/2026-11-30_cpu/session21/island/capture.py counterfactual=true \
  data.root="$ONE" output_dir=/tmp/s21data/island/cap_out_$T examples=0 threads=1 "counterfactual_kinds=[delete]" \
  "counterfactual_sources=[$SRC]" "counterfactual_fills=[rays]" $CK > /tmp/s21data/island/cap_$T.log 2>&1
echo "$T rc=$?"
