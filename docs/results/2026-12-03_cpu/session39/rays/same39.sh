#!/bin/bash
# same39.sh OUT: the five real-frame edits (session 35's specs; weights w39, boxes, one thread) with the base
# (/work/wt_rays_base, main 649a6841) and with the new code ($NEW, default /work/wt_rays/src); cmp of every output
# file but edit.json, and edit.json compared without its timings and paths (session 38's same.sh, adapted).
out=$1
new=${NEW:-/work/wt_rays/src}
cd /work/wt_rays_base
for s in t1 t1_180 t2 t2_45 d1; do
  for v in base new; do
    [ $v = base ] && pp=/work/wt_rays_base/src || pp=$new
    PYTHONPATH=$pp OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit input.image=tests/data/0006_30-deg-right_00043.png edits=/work/main/docs/results/2026-12-02_cpu/session35/lead/nearest/photo/$s.yaml run=/tmp/w39/outputs/demo/runs proposals=boxes threads=1 output_dir=$out/$v/$s overwrite=true progress=false > /dev/null 2>&1 || echo "$s $v failed"
  done
  files=$(cd $out/base/$s && find . -type f ! -name edit.json | sort)
  bad=0
  for f in $files; do cmp -s $out/base/$s/$f $out/new/$s/$f || { echo "$s $f DIFFERENT"; bad=1; }; done
  [ "$(cd $out/new/$s && find . -type f | sort)" = "$(cd $out/base/$s && find . -type f | sort)" ] || { echo "$s file lists differ"; bad=1; }
  /work/main/.venv/bin/python - "$out/base/$s/edit.json" "$out/new/$s/edit.json" <<'PY' || bad=1
import json, sys
VOL = ("time", "seconds", "ms", "elapsed", "wall", "dir", "path", "cpu", "started", "finished", "command", "argv")
def strip(x):
    if isinstance(x, dict):
        return {k: strip(v) for k, v in x.items() if not any(t in k.lower() for t in VOL)}
    if isinstance(x, list):
        return [strip(v) for v in x]
    return x
a, b = (strip(json.load(open(p))) for p in sys.argv[1:])
if a != b:
    print("edit.json differs beyond timings and paths"); sys.exit(1)
PY
  [ $bad = 0 ] && echo "$s identical ($(echo $files | wc -w) files, edit.json apart from timings)"
done
