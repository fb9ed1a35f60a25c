#!/bin/bash
# queue_main.sh: main's Table 1 photo rows on the tuning trees, one at a time (ground-truth masks first, then the
# semantic rows once the lead's demo has finished)
B=/tmp/s11data/semrain/base; T=/tmp/s11data/semrain
cd "$(dirname "$0")"
while pgrep -f "dbench.py $T/cache_m_35 $T/runs/m35_gt" > /dev/null; do sleep 10; done
./run.sh $B m37_gt $T/t1_37 gt $T/cache_m_37
while [ ! -e /tmp/s11data/demo/DONE ]; do sleep 10; done
./run.sh $B m35_semantic $T/t1_35 semantic $T/cache_m_35
./run.sh $B m37_semantic $T/t1_37 semantic $T/cache_m_37
