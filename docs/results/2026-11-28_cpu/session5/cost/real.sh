IMG=/work/wt/s5-cost/tests/data/0006_30-deg-right_00043.png
for side in after before; do
  if [ $side = after ]; then S=/work/wt/s5-cost; else S=/tmp/s5data/cost/main; fi
  PYTHONPATH=$S/src SDN3D_CONFIG_DIR=$S/conf OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=/tmp/s5data/cost/real_spec.yaml output_dir=/tmp/s5data/cost/real_$side threads=1 overwrite=true proposals=boxes > /tmp/s5data/cost/real_$side.log 2>&1
done
