#!/usr/bin/env bash
# second pair: the session start's code first, then main's
set -u
P=/tmp/s15data/lead/pair2
cd /tmp/s15data/lead/base_88b
uptime > $P/old_load_start.txt
PYTHONPATH=$PWD/src:$PWD OMP_WAIT_POLICY=PASSIVE /usr/bin/time -v /work/main/.venv/bin/python -m sdn3d.cli.demo output_dir=$P/old data_dir=$P/old/data > $P/old.log 2> $P/old_time_v.txt
uptime > $P/old_load_end.txt
cd /work/main
uptime > $P/new_load_start.txt
OMP_WAIT_POLICY=PASSIVE /usr/bin/time -v .venv/bin/sdn3d-demo output_dir=$P/new data_dir=$P/new/data > $P/new.log 2> $P/new_time_v.txt
uptime > $P/new_load_end.txt
