#!/usr/bin/env bash
# The main job: set up .venv and run the demo; results land in outputs/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup_env.sh
# Idle OpenMP threads sleep instead of spinning: much faster when the machine has other work to do.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-PASSIVE}"
.venv/bin/sdn3d-demo "$@"
