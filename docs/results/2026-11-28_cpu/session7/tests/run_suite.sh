#!/usr/bin/env bash
# usage: run_suite.sh TAG DURATIONS
tag=$1; dur=$2
cd /work/wt/s7-tests
out=/tmp/s7data/tests/$tag
ls /tmp/pytest-of-root/ > $out.dirs_before 2>/dev/null
uptime > $out.uptime
date -u >> $out.uptime
PYTHONPATH=$PWD/src:$PWD /usr/bin/time -v /work/main/.venv/bin/python -m pytest -q --durations=$dur -p no:cacheprovider > $out.txt 2> $out.time
echo rc=$? >> $out.uptime
uptime >> $out.uptime
date -u >> $out.uptime
ls /tmp/pytest-of-root/ > $out.dirs_after 2>/dev/null
for d in $(comm -13 <(sort $out.dirs_before) <(sort $out.dirs_after)); do
  echo "== $d" >> $out.du
  du -sh /tmp/pytest-of-root/$d >> $out.du
  du -sh /tmp/pytest-of-root/$d/* 2>/dev/null | sort -h | tail -40 >> $out.du
done
echo done >> $out.uptime
