# train.sh NAME SEED [OVERRIDES...]: the demo's semantic training (demo_short recipe) on the demo's data, one thread
set -u
N=$1; S=$2; shift 2
cd /tmp/w36
OMP_NUM_THREADS=1 .venv/bin/python -m sdn3d.cli.train branch=semantic experiment=demo_short data.root=/tmp/w36/outputs/demo/data seed=$S threads=1 datamodule.num_workers=0 trainer.enable_progress_bar=false '~callbacks.progress_bar' hydra.run.dir=/tmp/s36/sem/$N "$@" > /tmp/s36/sem/$N.log 2>&1
echo "$N rc=$? $(date -u +%T)" >> /tmp/s36/sem/done.txt
