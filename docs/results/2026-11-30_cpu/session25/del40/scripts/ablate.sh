#!/bin/bash
# ablate.sh SEED... : the ablation tree (make_ablation.py of main, $ABLTREE, default /tmp/s25data/del40/abl2) with
# each of 3D-SDN's removal parts off in turn (ABL=sil, shadow, effects, verge, keepout, thin, vp, and all of them: "sil,effects,thin,vp", which must
# equal the 2D paste), on the delete and occluder-removed entries, both rows, main's de-render caches (the ablation
# changes only the photo removal). Outputs /tmp/s25data/del40/t1/abl_<variant><SEED>_<row>.
HERE=$(cd "$(dirname "$0")" && pwd)
for V in ${VARIANTS:-sil shadow effects thin vp sil,effects,thin,vp}; do
  ABL=$V bash $HERE/t1.sh ${ABLTREE:-/tmp/s25data/del40/abl2} "abl_${V//,/+}_" "$@"
done
