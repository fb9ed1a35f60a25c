#!/bin/bash
# same.sh DIR_A DIR_B: are the call's outputs byte-identical (edit.json differs by timings and paths)?
for f in edited.png scene.json scene.npz edited_scene.json edited_scene.npz maps/photo_source.png; do
  if [ -e $1/$f ] || [ -e $2/$f ]; then cmp -s $1/$f $2/$f && echo "same $f" || echo "DIFFERENT $f"; fi
done
