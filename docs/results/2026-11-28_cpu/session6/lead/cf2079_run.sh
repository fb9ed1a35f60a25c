#!/bin/bash
B=/work/main/docs/results/2026-11-28_cpu/session5/turns/bench.sh; T=/tmp/s6data/lead/cf2079
bash $B /work/wt/lead-final $T /tmp/s6data/lead/cf2079_final 'examples=4'
bash $B /work/wt/lead-final $T /tmp/s6data/lead/cf2079_final_gt 'examples=4' run=/tmp/s5data/lead/demo 'counterfactual_sources=[gt]'
bash $B /work/wt/lead-base $T /tmp/s6data/lead/cf2079_base_gt 'examples=0' run=/tmp/s5data/lead/demo 'counterfactual_sources=[gt]'
