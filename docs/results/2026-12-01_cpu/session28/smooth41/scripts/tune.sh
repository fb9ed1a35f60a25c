#!/bin/bash
# tune.sh SRC TAG [OVERRIDE ...]: cf_turns.sh on the tuning trees (seeds in TREES, default "31 33") for both source
# scenes (ground-truth geometry (oracle), predicted), two at a time; outputs /tmp/s28/smooth41/cf/TAG<seed>_<source>.
SRC=$1; TAG=$2; shift 2
D=$(cd "$(dirname "$0")" && pwd); O=/tmp/s28/smooth41/cf; mkdir -p $O
for S in ${TREES:-31 33}; do
  bash "$D/cf_turns.sh" "$SRC" /tmp/s28/smooth41/tree$S "$O/${TAG}${S}_oracle" oracle "$@" &
  bash "$D/cf_turns.sh" "$SRC" /tmp/s28/smooth41/tree$S "$O/${TAG}${S}_semantic" semantic "$@"
  wait
done
