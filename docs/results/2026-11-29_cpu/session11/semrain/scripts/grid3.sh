#!/bin/bash
# grid3.sh: photo.mask_view_deg=90 (main's code otherwise) on the ground-truth-mask tuning rows, cached de-renders
B=/tmp/s11data/semrain/base; T=/tmp/s11data/semrain
cd "$(dirname "$0")"
./run.sh $B gMV37_gt $T/t1_37 gt $T/cache_m_37 photo.mask_view_deg=90
./run.sh $B gMV35_gt $T/t1_35 gt $T/cache_m_35 photo.mask_view_deg=90
