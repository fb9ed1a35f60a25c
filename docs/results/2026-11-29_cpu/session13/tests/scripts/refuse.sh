#!/usr/bin/env bash
# refuse.sh TREE: one sdn3d-train refused for a missing ckpt_path, with the code of TREE
cd /tmp/s13data/tests/refuse
unset PYTHONDONTWRITEBYTECODE  # bytecode of each tree written once, in the warm-up, as scripts/test.sh does
PYTHONPATH=$1/src:$1 OMP_NUM_THREADS=1 exec /work/main/.venv/bin/python -m sdn3d.cli.train branch=semantic hydra.run.dir=/tmp/s13data/tests/refuse/fresh ckpt_path=/tmp/s13data/tests/refuse/missing.ckpt summary_file=/tmp/s13data/tests/refuse/s.jsonl
