#!/usr/bin/env bash
# train.sh DATA RUN_DIR THREADS: the demo's semantic recipe (experiment=demo_short) on DATA, seed 0.
set -euo pipefail
cd /work/main
OMP_WAIT_POLICY=PASSIVE .venv/bin/sdn3d-train branch=semantic experiment=demo_short data.root=$1 seed=0 threads=$3 \
  datamodule.num_workers=0 trainer.enable_progress_bar=false '~callbacks.progress_bar' hydra.run.dir=$2 "${@:4}"
