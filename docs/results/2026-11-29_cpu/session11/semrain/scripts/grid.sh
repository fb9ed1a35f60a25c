#!/bin/bash
# grid.sh SOURCE SEED...: main's code with one photo setting changed per run, on the cached de-renders of main's rows
# (a photo setting does not change the de-render), after main's seed-37 semantic row has finished
p=$1; shift; B=/tmp/s11data/semrain/base; T=/tmp/s11data/semrain
cd "$(dirname "$0")"
while pgrep -f "runs/m37_semantic.dump" > /dev/null; do sleep 10; done
for s in "$@"; do
  ./run.sh $B gMV${s}_$p $T/t1_$s $p $T/cache_m_$s photo.mask_view_deg=90
  ./run.sh $B gCS${s}_$p $T/t1_$s $p $T/cache_m_$s photo.contact_shadow=0
  ./run.sh $B gUB${s}_$p $T/t1_$s $p $T/cache_m_$s photo.unseen=body
done
