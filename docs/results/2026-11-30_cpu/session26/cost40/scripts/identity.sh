#!/bin/bash
# identity.sh OUT: one sdn3d-edit call per code tree (main's plain tree and this branch's archive) on the spec31 edit
# (624x192 seed-31 Table 1 frame, 10 boxes, one rotate; w0 run=, threads=2), then every output file compared byte
# for byte; edit.json compared with its timings and paths left out (they differ by construction). BRANCH: the
# branch tree (default /tmp/s26data/cost40/tree_cost40); SDN3D_MESHES_CACHE passes through (an empty one: cold).
OUT=$1; mkdir -p $OUT
SPEC=/work/wt/cost40/docs/results/2026-11-28_cpu/session4/cost/spec31.yaml
for T in main=/tmp/s26data/lead/base_9fa cost40=${BRANCH:-/tmp/s26data/cost40/tree_cost40}; do
  NAME=${T%%=*}; CODE=${T#*=}
  (cd $CODE && OMP_NUM_THREADS=1 PYTHONPATH=$CODE/src SDN3D_CONFIG_DIR=$CODE/conf nice -n 5 /work/main/.venv/bin/python \
     -m sdn3d.cli.edit input.image=/tmp/s26data/cost40/in31.png edits=$SPEC run=/tmp/s21data/demo/out threads=2 \
     output_dir=$OUT/$NAME overwrite=true > $OUT/$NAME.log 2>&1; echo "$NAME rc=$?")
done
cd $OUT && for f in $(cd main && find . -type f | sort); do
  if [ "$f" = "./edit.json" ]; then continue; fi
  if cmp -s main/$f cost40/$f; then echo "identical $f"; else echo "DIFFERS $f"; fi
done
/work/main/.venv/bin/python - "$OUT" <<'PY'
import json, sys
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not k.endswith("_ms") and k not in ("timings_ms", "output_dir",
                                                                                        "created", "started")}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
a, b = (json.load(open(f"{sys.argv[1]}/{n}/edit.json")) for n in ("main", "cost40"))
print("edit.json without timings and output paths:", "identical" if strip(a) == strip(b) else "DIFFERS")
if strip(a) != strip(b):
    for k in a:
        if strip(a.get(k)) != strip(b.get(k)):
            print("  differs at", k)
PY
