# One sdn3d-edit call at 624x192 with 10 box objects (dense31 tuning frame, + the semantic branch's proposals, all
# fitted), after (A) vs before (B), farm-bench pairs, threads=1 then threads=2.
C=/tmp/s4data/cost; IMG=$C/dense31/vkitti_1.3.1_rgb/0006/clone/00000.png; PY=/work/main/.venv/bin/python
for T in 1 2; do
  uptime; ps -eo pcpu,etime,args --sort=-pcpu | head -8 | cut -c1-140
  farm-bench -n 3 --warmup 1 --timeout 1500 \
    --vs "env PYTHONPATH=$C/base/src SDN3D_CONFIG_DIR=$C/base/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=$C/spec31.yaml output_dir=$C/edit_before_t$T threads=$T" \
    -- env PYTHONPATH=$C/after/src SDN3D_CONFIG_DIR=$C/after/conf OMP_NUM_THREADS=$T $PY -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=$C/spec31.yaml output_dir=$C/edit_after_t$T threads=$T
done
uptime
