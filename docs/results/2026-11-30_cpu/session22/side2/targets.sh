#!/bin/bash
# targets.sh CODE NAME TREE SOURCE KEYS: the branch (or any code tree CODE) on the targets KEYS (comma-separated
# pair-key prefixes, the ones rules.py found changed) of TREE, source SOURCE, through record.sh (fill rays, turns,
# threads 1, nice 5). Out: /tmp/s22data/side2/probe/NAME/counterfactual.json.
CODE=$1; NAME=$2; TREE=$3; SOURCE=$4
KEYS=$5 bash "$(dirname "$0")/record.sh" "$CODE" "$TREE" "$SOURCE" "$NAME"
