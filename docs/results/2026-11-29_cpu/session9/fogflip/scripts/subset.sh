#!/bin/bash
# subset.sh TREE OUT IDX... : a tree of symlinks with only the named benchmark entries (in that order)
tree=$1; out=$2; shift 2; rm -rf $out; mkdir -p $out
for f in $tree/*; do [ "$(basename $f)" != vkitti_edit_benchmark.json ] && ln -s $f $out/; done
python3 -c "
import json,sys; b=json.load(open('$tree/vkitti_edit_benchmark.json')); json.dump([b[int(i)] for i in sys.argv[1:]], open('$out/vkitti_edit_benchmark.json','w'))" "$@"
