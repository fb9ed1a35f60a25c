#!/bin/bash
# grid2.sh: photo.mask_view_deg=90 (main's code otherwise) on the remaining tuning rows, cached de-renders
B=/tmp/s11data/semrain/base; T=/tmp/s11data/semrain
cd "$(dirname "$0")"
while pgrep -f "runs/gMV37_semantic.dump" > /dev/null; do sleep 5; done
./run.sh $B gMV35_semantic $T/t1_35 semantic $T/cache_m_35 photo.mask_view_deg=90
./run.sh $B gMV37_gt $T/t1_37 gt $T/cache_m_37 photo.mask_view_deg=90
./run.sh $B gMV35_gt $T/t1_35 gt $T/cache_m_35 photo.mask_view_deg=90
