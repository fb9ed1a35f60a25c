#!/bin/bash
# queue.sh SRC TAG JOB...: bench.sh runs one after another (one process: the machine's 2 cores are shared) with the
# code of SRC, each JOB TREE:SOURCE:KIND (e.g. cf31:oracle:delete), outputs /tmp/s21data/island/bench/TAG_TREE_SOURCE_KIND,
# fill rays (the default). Trees: /tmp/s21data/trees/TREE, else /tmp/s21data/island/TREE (the held-out one).
S=$1; T=$2; shift 2
D=$(dirname "$(readlink -f "$0")")
mkdir -p /tmp/s21data/island/bench
for j in "$@"; do
  IFS=: read -r tree source kind <<< "$j"
  root=/tmp/s21data/trees/$tree
  [ -d "$root" ] || root=/tmp/s21data/island/$tree
  bash "$D/bench.sh" "$S" "$root" "/tmp/s21data/island/bench/${T}_${tree}_${source}_${kind}" "$source" "[rays]" "[$kind]"
done
