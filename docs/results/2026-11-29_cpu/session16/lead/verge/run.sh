#!/bin/bash
# run.sh: what the lead ran for the verge-run rule (session 16), from /work/main. BASE: git archive of 9f19738
# (the session's start); NEW: git archive of 61c5ccb. Tuning deletes (cf31, cf33, cf39; ground-truth geometry,
# oracle; rays) with session 14's roadfill/bench.sh, both codes; held-out cf2151 (session 5's gen_cf.py recipe,
# generated after 61c5ccb, measured once): oracle rays + learnt, predicted rays; the real frame by session 15's
# sides/real.sh (both codes), measured by session 14's roadfill/real_measure.py; tables by session 12's paired.py.
set -u
B=docs/results/2026-11-29_cpu/session14/roadfill/bench.sh; L=/tmp/s16data/lead/del; BASE=/tmp/s16data/lead/base_9f1
NEW=/tmp/s16data/lead/new
for T in 31:/tmp/s11data/lead/cf31 33:/tmp/s14data/ends/cf33 39:/tmp/s14data/roadfill/cf39; do
  bash $B $NEW ${T#*:} $L/t${T%%:*}_new oracle '[rays]'; bash $B $BASE ${T#*:} $L/t${T%%:*}_base oracle '[rays]'
done
(cd $NEW && PYTHONPATH=$NEW/src /work/main/.venv/bin/python docs/results/2026-11-28_cpu/session5/turns/gen_cf.py \
  /tmp/s16data/lead/cf2151 2151 0006,0018,0020 6)
for C in new:$NEW base_9f1:$BASE; do
  bash $B ${C#*:} /tmp/s16data/lead/cf2151 $L/h2151_${C%%:*}_oracle oracle '[rays,learnt]'
  bash $B ${C#*:} /tmp/s16data/lead/cf2151 $L/h2151_${C%%:*}_pred semantic '[rays]'
done
bash docs/results/2026-11-29_cpu/session15/sides/real.sh base:$BASE,new:$NEW /tmp/s16data/lead/real1
