#!/usr/bin/env bash
# The test command: set up .venv, lint, run the default (fast, CPU) test suite.
# Extra arguments go to pytest, e.g. `bash scripts/test.sh -m slow` for the long tests.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup_env.sh

# apt_install WHAT PACKAGE...: install Debian packages (as root, or through password-less sudo), or say that WHAT
# is skipped because they cannot be installed here (no root, no apt-get). One `apt-get update` per run.
apt_updated=
apt_install() {
    local what=$1 as_root
    shift
    if [ "$(id -u)" = 0 ]; then
        as_root=()
    elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
        as_root=(sudo -n)
    else
        as_root=(none)
    fi
    if [ "${as_root[0]:-}" != none ] && command -v apt-get >/dev/null 2>&1; then
        echo "[test] installing $* (apt-get) for $what"
        [ -n "$apt_updated" ] || "${as_root[@]}" apt-get update -qq
        apt_updated=1
        "${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$@" >/dev/null
    else
        echo "[test] $* cannot be installed here (no root, no apt-get): $what are skipped (apt-get install $*)" >&2
    fi
}

# The browser tests of sdn3d-app (tests/test_app_browser.py) drive Debian's chromium through Selenium; Selenium's
# own browser downloads are not reachable, so the system's chromium and chromedriver are installed here. Without
# them the tests are skipped, except on CI (CI=true), where they fail.
if ! command -v chromium >/dev/null 2>&1 || ! command -v chromedriver >/dev/null 2>&1; then
    apt_install "the browser tests" chromium chromium-driver
fi
# The soft silhouette's C++ kernel (src/sdn3d/render/soft_kernel.cpp) is compiled with g++ on first use; without a
# compiler the PyTorch path draws instead and the kernel's tests are skipped, except on CI (CI=true), where that is a
# failure (build-essential provides g++).
if ! command -v g++ >/dev/null 2>&1; then
    apt_install "the soft silhouette kernel's tests" build-essential
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
# Two pytest workers (pytest-xdist), one a core: most tests wait on a child process's start-up (import torch) or on
# one thread's arithmetic (tests/conftest.py sets one torch thread), so two workers about halve the wall time on CI's
# 2 cores. SDN3D_TEST_WORKERS sets how many; SDN3D_TEST_WORKERS=1 runs the tests one after another in this process.
# A -n/--numprocesses on the command line wins over both.
workers=${SDN3D_TEST_WORKERS:-2}
parallel=(-n "$workers" --dist load)
for arg in "$@"; do
    case $arg in -n|-n[0-9]*|--numprocesses|--numprocesses=*) parallel=() ;; esac
done
[ "$workers" != 1 ] || parallel=()
.venv/bin/python -m pytest "${parallel[@]}" "$@"
