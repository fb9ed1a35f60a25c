#!/usr/bin/env bash
# Side by side: the changed test files at f45beb0 (base) and at this branch (new), run at the same time.
FILES="tests/test_train_ops.py tests/test_train_faults.py tests/test_reliability_resume.py tests/test_reliability_relocate.py tests/test_reliability_locks.py tests/test_inference_export.py"
run() { # dir tag
  cd $1 && PYTHONPATH=$PWD/src:$PWD /usr/bin/time -f "cpu=%U+%S wall=%e" /work/main/.venv/bin/python -m pytest -q -p no:cacheprovider \
    -o tmp_path_retention_policy=failed --durations=0 --durations-min=0 $FILES > /tmp/s7data/tests/paired_$2.txt 2>&1
}
uptime > /tmp/s7data/tests/paired.uptime
run /tmp/s7data/tests/base base &
run /work/wt/s7-tests new &
wait
uptime >> /tmp/s7data/tests/paired.uptime
