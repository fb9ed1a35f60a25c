#!/usr/bin/env bash
# CUDA checks and GPU timings in one go, for a machine with one NVIDIA GPU:
#
#   bash benchmarks/cuda_suite.sh OUT_DIR [STEP ...]
#
# Steps (default: all but `demo`, in this order; each one's stdout/stderr goes to OUT_DIR/<step>.log and its
# JSON, where it has one, to OUT_DIR/<step>.json; a failing step is reported and the next one runs):
#   tests      pytest tests/test_cuda.py (renderers, de-render/edit/render and training agree with the CPU)
#   speed      semantic / geometric / textural / renderer speed benchmarks with --device cuda
#   latency    per-edit latency at 624x192 (benchmarks/edit_latency.py --device cuda, demo and paper nets)
#   semantic   the documented CPU semantic run (2 epochs at 312x96, fp32) on the GPU, and a 40-epoch curve
#   demo       sdn3d-demo device=cuda (the README's demo on the GPU)
# Uses `python3` as found (the package installed, or PYTHONPATH=src:. from the repository root) and a
# synthetic dataset it writes to OUT_DIR/synth (or $SDN3D_SYNTH if set).
set -u
OUT=${1:?usage: bash benchmarks/cuda_suite.sh OUT_DIR [STEP ...]}
shift
STEPS=${*:-tests speed latency semantic}
mkdir -p "$OUT"
PY=${PYTHON:-python3}
export PYTHONUNBUFFERED=1
THREADS=${THREADS:-8}
SYNTH=${SDN3D_SYNTH:-$OUT/synth}

step() {  # step NAME TIMEOUT_S COMMAND...: run, log, report the status and the wall time
  local name=$1 limit=$2
  shift 2
  local t0=$SECONDS
  timeout "$limit" "$@" >"$OUT/$name.log" 2>&1
  local rc=$?
  echo "[cuda_suite] $name: exit $rc, $((SECONDS - t0)) s" | tee -a "$OUT/steps.txt"
}

$PY - <<'EOF' | tee "$OUT/device.txt"
import torch
print("torch", torch.__version__, "cuda", torch.version.cuda, "gpu", torch.cuda.get_device_name())
EOF
if [ ! -f "$SYNTH/_SUCCESS" ]; then
  step synth 300 $PY -m sdn3d.cli.synth output_dir="$SYNTH" frames_per_sequence=20 workers="$THREADS" overwrite=true
fi

for s in $STEPS; do
  case $s in
    tests)
      step tests 400 $PY -m pytest -q -p no:cacheprovider tests/test_cuda.py ;;
    speed)
      step speed_semantic 200 $PY benchmarks/semantic.py speed --device cuda --size 624 192 --batch 8 --repeats 10
      step speed_geometric_64 200 $PY benchmarks/geometric.py --root "$SYNTH" --device cuda --crop-size 64 --steps 20
      step speed_geometric_128 200 $PY benchmarks/geometric.py --root "$SYNTH" --device cuda --crop-size 128 --steps 20
      step speed_textural 300 $PY benchmarks/textural.py speed --device cuda --data-root "$SYNTH" --repeats 10
      step speed_renderer 200 $PY benchmarks/renderer.py --device cuda ;;
    latency)
      step latency 400 $PY benchmarks/edit_latency.py --device cuda --presets demo paper --semantic --no-reference \
        --repeats 5 --out "$OUT/latency.json" ;;
    semantic)
      # The documented CPU run (benchmarks/semantic.py train --size 312 96 --epochs 2 --threads 1), same arithmetic.
      step semantic_same_run 300 $PY benchmarks/semantic.py train --device cuda --root "$SYNTH" --size 312 96 \
        --epochs 2 --threads "$THREADS" --out "$OUT/semantic_same_run"
      step semantic_curve_312 500 $PY benchmarks/semantic.py train --device cuda --precision 16-mixed --root "$SYNTH" \
        --size 312 96 --epochs 40 --val-every 2 --threads "$THREADS" --out "$OUT/semantic_curve_312"
      step semantic_curve_624 500 $PY benchmarks/semantic.py train --device cuda --precision 16-mixed --root "$SYNTH" \
        --size 624 192 --epochs 40 --val-every 2 --threads "$THREADS" --out "$OUT/semantic_curve_624" ;;
    demo)
      step demo 900 $PY -m sdn3d.cli.demo device=cuda threads="$THREADS" output_dir="$OUT/demo" \
        data_dir="$OUT/demo/data" ;;
    *)
      echo "[cuda_suite] unknown step $s" | tee -a "$OUT/steps.txt" ;;
  esac
done
# The JSON each benchmark printed last (its result), beside its log.
for log in "$OUT"/*.log; do
  $PY - "$log" <<'EOF'
import json, sys
from pathlib import Path
log = Path(sys.argv[1]); text = log.read_text(errors="replace")
start = text.rfind("\n{")
if start >= 0:
    try:
        obj = json.loads(text[start + 1:text.rfind("}") + 1])
        log.with_suffix(".json").write_text(json.dumps(obj, indent=1) + "\n")
    except json.JSONDecodeError:
        pass
EOF
done
cat "$OUT/steps.txt"
