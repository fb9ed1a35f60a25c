#!/bin/bash
# compare.sh OUT A B: outputs.sh's outputs of codes A and B compared (session15/cost2/same_outputs.py), printed.
set -u
O=$1; A=$2; B=$3
R=$(cd "$(dirname "$0")/../../../.." && pwd); PY=/work/main/.venv/bin/python; SAME=$R/2026-11-29_cpu/session15/cost2/same_outputs.py
echo "$A against $B, $(date -u +%T)"
echo "14 latency edits, a fresh source per edit:"; $PY $SAME $O/$A/edits.npz $O/$B/edits.npz
echo "14 latency edits, one source per frame (--reuse-source):"; $PY $SAME $O/$A/reuse.npz $O/$B/reuse.npz
echo "cf31 counterfactual pairs (counterfactual.md byte-compared with cmp):"
cmp $O/$A/cf31/counterfactual.md $O/$B/cf31/counterfactual.md && echo "counterfactual.md byte-identical"
$PY $SAME $O/$A/cf31 $O/$B/cf31
echo "real frame, one EditSession:"; $PY $SAME $O/$A/real $O/$B/real
