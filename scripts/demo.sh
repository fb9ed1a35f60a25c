#!/usr/bin/env bash
# The main job: set up .venv and run the demo; results land in outputs/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup_env.sh
.venv/bin/sdn3d-demo "$@"
