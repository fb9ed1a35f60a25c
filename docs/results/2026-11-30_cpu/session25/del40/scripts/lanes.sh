#!/bin/bash
# lanes.sh A|B: the session's ablation order, two lanes of ablate.sh (the losing trees 13, 11 and 31 first).
HERE=$(cd "$(dirname "$0")" && pwd)
if [ "$1" = A ]; then
  VARIANTS=effects bash $HERE/ablate.sh 13 11
  VARIANTS="verge keepout" bash $HERE/ablate.sh 31 13 11
else
  VARIANTS=effects bash $HERE/ablate.sh 35 37
  VARIANTS=sil bash $HERE/ablate.sh 13 11
  VARIANTS=thin bash $HERE/ablate.sh 31 13
  VARIANTS="vp sil,effects,thin,vp" bash $HERE/ablate.sh 13
fi
