#!/usr/bin/env bash
# The environments of these measurements: the shared /work/main/.venv (an editable install of main, left untouched)
# seen through two thin venvs, one with this branch's tree first on sys.path and one with the old tree
# (/tmp/s13data/tests/old: `git archive 97b891e`), so that a test's child process started with its own PYTHONPATH
# (tests/test_train_ops.py's _cli) runs the tree under test as a fresh clone's editable install would. pytest-xdist
# 3.8.0 and execnet 2.1.2 went into /tmp/s13data/tests/xdist (pip install --target; its copy of pytest removed).
set -eu
cd /tmp/s13data/tests
for pair in venv:/work/wt/tests venv_old:/tmp/s13data/tests/old; do
    name=${pair%%:*} tree=${pair#*:}
    /root/.pyenv/versions/3.11.7/bin/python3 -m venv --without-pip "$name"
    site=$name/lib/python3.11/site-packages
    printf '%s/src\n%s\n/tmp/s13data/tests/xdist\n' "$tree" "$tree" > "$site/00_sdn3d_worktree.pth"
    echo 'import site; site.addsitedir("/work/main/.venv/lib/python3.11/site-packages")' > "$site/01_main_venv.pth"
done
