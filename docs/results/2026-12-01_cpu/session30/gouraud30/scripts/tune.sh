#!/bin/bash
# tune.sh SRC NAME SOURCE [OVERRIDE ...]: cf_turns.sh on both tuning trees (seeds 31 and 33, main's generator) with the
# code of the plain tree SRC, one after the other, into /tmp/s30/gouraud30/cf/cf{31,33}/NAME_SOURCE.
SRC=$1; NAME=$2; S=$3; D=$(cd "$(dirname "$0")" && pwd); H=/tmp/s30/gouraud30
for T in 31 33; do
  mkdir -p $H/cf/cf$T
  bash $D/cf_turns.sh $SRC $H/tree$T $H/cf/cf$T/${NAME}_$S $S "${@:4}"
done
