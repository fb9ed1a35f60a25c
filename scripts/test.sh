#!/usr/bin/env bash
# The test command: set up .venv, lint, run the default (fast, CPU) test suite.
# Extra arguments go to pytest, e.g. `bash scripts/test.sh -m slow` for the long tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup_env.sh

# The browser tests of sdn3d-app (tests/test_app_browser.py) drive Debian's chromium through Selenium; Selenium's
# own browser downloads are not reachable, so the system's chromium and chromedriver are installed here (as root,
# or through password-less sudo). Without them the tests are skipped, except on CI (CI=true), where they fail.
if ! command -v chromium >/dev/null 2>&1 || ! command -v chromedriver >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ]; then
        as_root=()
    elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
        as_root=(sudo -n)
    else
        as_root=(none)
    fi
    if [ "${as_root[0]:-}" != none ] && command -v apt-get >/dev/null 2>&1; then
        echo "[test] installing chromium and chromium-driver (apt-get) for the browser tests"
        "${as_root[@]}" apt-get update -qq
        "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver >/dev/null
    else
        echo "[test] chromium / chromedriver are missing and cannot be installed here (no root, no apt-get):" \
             "the browser tests are skipped (apt-get install chromium chromium-driver)" >&2
    fi
fi
# The soft silhouette's C++ kernel (src/sdn3d/render/soft_kernel.cpp) is compiled with g++ on first use; without a
# compiler the PyTorch path draws instead and the kernel's tests are skipped, except on CI (CI=true), where that is a
# failure (build-essential provides g++).
if ! command -v g++ >/dev/null 2>&1; then
    if [ "$(id -u)" = 0 ]; then
        as_root=()
    elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
        as_root=(sudo -n)
    else
        as_root=(none)
    fi
    if [ "${as_root[0]:-}" != none ] && command -v apt-get >/dev/null 2>&1; then
        echo "[test] installing build-essential (apt-get) for the soft silhouette's C++ kernel"
        "${as_root[@]}" apt-get update -qq
        "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq build-essential >/dev/null
    else
        echo "[test] g++ is missing and cannot be installed here: the C++ kernel's tests are skipped" >&2
    fi
fi
if ! .venv/bin/python -c "import selenium" 2>/dev/null; then
    echo "[test] installing the browser extra (selenium)"
    .venv/bin/python -m pip install --quiet --disable-pip-version-check -e ".[browser]" 2>&1 | grep -v "^WARNING: Location" || true
fi

.venv/bin/ruff check .
# The tests start many CLI processes (sdn3d-train, -edit, -bench); with bytecode written once (__pycache__, ignored by
# git) each start skips compiling the project's sources again, about 1 CPU s a process where the environment sets
# PYTHONDONTWRITEBYTECODE (docs/results/2026-11-28_cpu/session7/tests/).
unset PYTHONDONTWRITEBYTECODE
.venv/bin/python -m pytest "$@"
