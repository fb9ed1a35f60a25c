#!/bin/bash
# variants.sh SRC NAME TREES OVERRIDE...: the branch's deletes (ground-truth geometry (oracle), rays) on tuning trees
# TREES (e.g. "cf33 cf39") with photo overrides (e.g. +photo.leftover_step=20), one after another, outputs
# /tmp/s21data/speck/var/NAME_TREE; pair each with main's run by paired.py.
S=$1; N=$2; TREES=$3; shift 3
D=$(dirname "$(readlink -f "$0")")
mkdir -p /tmp/s21data/speck/var
for t in $TREES; do
  bash "$D/bench.sh" "$S" "/tmp/s21data/trees/$t" "/tmp/s21data/speck/var/${N}_$t" oracle "[rays]" "[delete]" "$@"
done
