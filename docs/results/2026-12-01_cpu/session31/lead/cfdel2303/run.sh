#!/bin/bash
B=/tmp/s31/lead/cf/base
export PYTHONPATH=$B/src:$B OMP_NUM_THREADS=1
echo "gen start $(date -u +%T)" >> /tmp/s31/lead/cf/log.txt
nice -n 5 /work/main/.venv/bin/python /work/main/docs/results/2026-12-01_cpu/session31/lead/cfdel2303/gen_cf.py /tmp/s31/lead/cf/t2303 2303 0001,0002,0006,0018,0020,0003,0004,0005 8 > /tmp/s31/lead/cf/gen.log 2>&1
echo "gen rc=$? $(date -u +%T)" >> /tmp/s31/lead/cf/log.txt
cd $B && nice -n 5 /work/main/.venv/bin/python -m sdn3d.cli.bench counterfactual=true data.root=/tmp/s31/lead/cf/t2303 run=/tmp/s31/ci/outputs/demo 'counterfactual_kinds=[delete]' 'counterfactual_sources=[oracle]' 'counterfactual_fills=[auto,telea,patchmatch,rays,learnt]' threads=1 output_dir=/tmp/s31/lead/cf/out > /tmp/s31/lead/cf/bench.log 2>&1
echo "bench rc=$? $(date -u +%T)" >> /tmp/s31/lead/cf/log.txt
