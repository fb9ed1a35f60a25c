#!/bin/bash
# run_cf.sh SRC TAG [OVERRIDE ...]: the counterfactual delete bench (cf_bench.sh: fill rays, kind delete) on the three
# tuning cf trees (cf31, cf33, cf39), predicted (semantic) then ground-truth geometry (oracle), with the code tree SRC,
# two at a time (SOURCES= to pick, default "semantic oracle");
# outputs /tmp/s27data/shadow41/cf/TAG<seed>_<source>/counterfactual.json.
SRC=$1; TAG=$2; shift 2
D=$(dirname "$0"); O=/tmp/s27data/shadow41/cf
for S in ${SOURCES:-semantic oracle}; do
  bash "$D/cf_bench.sh" "$SRC" /tmp/s21data/trees/cf31 "$O/${TAG}31_$S" $S "[rays]" "[delete]" "$@" &
  bash "$D/cf_bench.sh" "$SRC" /tmp/s21data/trees/cf33 "$O/${TAG}33_$S" $S "[rays]" "[delete]" "$@"
  wait
  bash "$D/cf_bench.sh" "$SRC" /tmp/s21data/trees/cf39 "$O/${TAG}39_$S" $S "[rays]" "[delete]" "$@"
done
