#!/bin/bash
# held-out Table 1 pictures (seed 2083, predicted proposals), two entries: start, final, final with ray_haze=0 (reporting only)
D=/tmp/s7data/haze/pics; mkdir -p $D
one() { code=$1; tag=$2; shift 2
  cd $code && PYTHONDONTWRITEBYTECODE=1 PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s7data/haze/t1_one.py /tmp/s7data/haze/cache_t1_2083_semantic_derender $D/t1_2083_semantic_derender_$tag.npz 56,85 data.root=/tmp/s7data/haze/t1_2083 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' "proposals=[semantic]" scene=derender threads=1 examples=0 output_dir=$D/out_2083_$tag "$@" > $D/t1_2083_$tag.log 2>&1; echo "$tag rc=$?"; }
one /tmp/s7data/haze/src_final off +photo.ray_haze=0 &
one /tmp/s7data/haze/src_start always &
one /tmp/s7data/haze/src_final gated &
wait
