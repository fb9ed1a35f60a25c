#!/usr/bin/env bash
# usage: runfull.sh TAG [pytest args...]  -- one full default-suite run of /work/wt/tests, timed
set -u
tag=$1; shift
cd /work/wt/tests
unset PYTHONDONTWRITEBYTECODE
export PYTHONPATH=/tmp/s13data/tests/xdist:$PWD/src:$PWD OMP_NUM_THREADS=1
out=/tmp/s13data/tests/runs/$tag; mkdir -p $out
nice -n 10 /usr/bin/time -v -o $out/time.txt ${PY:-/work/main/.venv/bin/python} -m pytest -q -p no:cacheprovider --basetemp=/tmp/s13data/tests/bt_$tag --durations=0 --junitxml=$out/junit.xml "$@" > $out/log.txt 2>&1
echo "rc=$?" >> $out/log.txt
