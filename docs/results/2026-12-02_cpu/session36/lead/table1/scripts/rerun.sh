# rerun.sh SEED: the predicted row of held-out tree SEED (already generated) with the final code (/tmp/s36_final)
set -u
S=$1; B=/tmp/s36/t1held; CODE=/tmp/s36_final
export PYTHONPATH=$CODE/src OMP_NUM_THREADS=1 SDN3D_CONFIG_DIR=$CODE/conf
(cd $CODE && /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=$B/trees/t1d_$S 'data.image_size=[312,96]' run=/tmp/w36/outputs/demo 'compose=[photo]' 'proposals=[semantic]' scene=derender threads=1 examples=0 output_dir=$B/final/${S}_semantic > $B/final_${S}.log 2>&1)
echo "$S final semantic rc=$? $(date -u +%T)" >> $B/run.log
