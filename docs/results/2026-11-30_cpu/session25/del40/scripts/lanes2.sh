#!/bin/bash
# lanes2.sh C|D: the second round of ablations (after lanes.sh A and B): keepout on the other tuning trees;
# C: 35 37; D: 33 39 with effects and shadow too.
HERE=$(cd "$(dirname "$0")" && pwd)
if [ "$1" = C ]; then
  VARIANTS=keepout bash $HERE/ablate.sh 35 37
elif [ "$1" = D ]; then
  VARIANTS="keepout effects shadow" bash $HERE/ablate.sh 33 39
fi
