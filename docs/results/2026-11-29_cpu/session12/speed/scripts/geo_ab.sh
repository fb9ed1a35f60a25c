#!/bin/bash
# geo_ab.sh: the demo's geometric training (session 11's idle demo data, seed 0, threads 1), base tree then this branch
for T in base new; do TREE=$([ $T = base ] && echo /tmp/s12data/speed/base || echo /work/wt/speed)
  (cd $TREE && PYTHONPATH=$TREE/src:$TREE OMP_NUM_THREADS=1 SDN3D_CONFIG_DIR=$TREE/conf nice -n 5 /usr/bin/time -f "%U user %S sys %e wall" /work/main/.venv/bin/python -m sdn3d.cli.train branch=geometric experiment=demo_short data.root=/tmp/s11data/demo_final/data seed=0 threads=1 datamodule.num_workers=0 run_dir=/tmp/s12data/speed/geo_$T trainer.enable_progress_bar=false '~callbacks.progress_bar' summary_file=/tmp/s12data/speed/geo_$T.jsonl > /tmp/s12data/speed/geo_$T.log 2>&1)
  tail -1 /tmp/s12data/speed/geo_$T.log
done
