# eval.sh NAME TREE_TAG TREE: the predicted Table 1 photo row of TREE with semantic weights NAME (best checkpoint of
# /tmp/s36/sem/NAME, or w36 for NAME=w36), w36's geometric and textural; and maskdiag on it
set -u
N=$1; TAG=$2; T=$3
if [ "$N" = w36 ]; then CK=/tmp/w36/outputs/demo/runs/semantic/checkpoints/inference.pt; else CK=$(ls /tmp/s36/sem/$N/checkpoints/best-*.ckpt | head -1); fi
cd /tmp/s36_lead_base
SDN3D_CONFIG_DIR=/tmp/s36_lead_base/conf PYTHONPATH=/tmp/s36_lead_base/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.bench data.root=$T 'data.image_size=[312,96]' run=/tmp/w36/outputs/demo checkpoints.semantic=$CK 'compose=[photo]' 'proposals=[semantic]' scene=derender threads=1 examples=0 output_dir=/tmp/s36/sem/bench/${N}_$TAG > /tmp/s36/sem/bench/${N}_$TAG.log 2>&1
echo "$N $TAG bench rc=$? $(date -u +%T)" >> /tmp/s36/sem/bench/done.txt
