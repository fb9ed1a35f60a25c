#!/usr/bin/env bash
# Create or refresh the project's virtual environment in .venv.
# torch is installed first and pinned (torch==2.13.0): its CPU wheel is at hand on the
# project's machines, while a looser pin would pull a multi-GB CUDA build.
# Re-installs only when pyproject.toml changed (a stamp in .venv remembers its hash).
set -euo pipefail
cd "$(dirname "$0")/.."
PYTHON="${PYTHON:-python3}"
if [ ! -x .venv/bin/python ]; then
    echo "[setup] creating .venv with $($PYTHON --version)"
    "$PYTHON" -m venv .venv
fi
stamp=.venv/.sdn3d-install-stamp
want="$(sha256sum pyproject.toml | cut -d' ' -f1)"
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
    echo "[setup] installing torch==2.13.0, then sdn3d with its dependencies (a few minutes on a new machine)"
    .venv/bin/python -m pip install --quiet --disable-pip-version-check "torch==2.13.0" 2>&1 | grep -v "^WARNING: Location" || true
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -e ".[dev]" 2>&1 | grep -v "^WARNING: Location" || true
    .venv/bin/python -c "import torch, lightning, hydra, kornia, trimesh, torchmetrics, sdn3d" \
        || { echo "[setup] installation failed" >&2; exit 1; }
    echo "$want" > "$stamp"
else
    echo "[setup] .venv is up to date"
fi
