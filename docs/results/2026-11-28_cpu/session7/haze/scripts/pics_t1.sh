#!/bin/bash
# Table 1 pictures: chosen entries, three codes/settings, cached de-render
D=/tmp/s7data/haze/pics; mkdir -p $D
one() { code=$1; tag=$2; tree=$3; p=$4; sc=$5; idx=$6; shift 6; tn=$(basename $tree)
  cd $code && PYTHONDONTWRITEBYTECODE=1 PYTHONPATH=$code/src:$code OMP_NUM_THREADS=1 /work/main/.venv/bin/python /tmp/s7data/haze/t1_one.py /tmp/s7data/haze/cache_${tn}_${sc} $D/${tn}_${p}_${sc}_${tag}.npz $idx data.root=$tree 'data.image_size=[312,96]' run=/tmp/s5data/lead/demo 'compose=[photo]' "proposals=[$p]" scene=$sc threads=1 examples=0 output_dir=$D/out_${tn}_${p}_${sc}_${tag} "$@" > $D/${tn}_${p}_${sc}_${tag}.log 2>&1; echo "$tag $tn $p $sc rc=$?"; }
S=/tmp/s7data/haze/src_start; G=/tmp/s7data/haze/src_gated
for spec in "/tmp/s6data/lead/t1_35 semantic derender 38" "/tmp/s7data/haze/t1_37 gt oracle 72,125,56,111"; do set -- $spec
  one $G off $1 $2 $3 $4 +photo.ray_haze=0
  one $S always $1 $2 $3 $4
  one $G gated $1 $2 $3 $4
done
