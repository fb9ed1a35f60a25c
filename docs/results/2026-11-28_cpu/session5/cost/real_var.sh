IMG=/work/wt/s5-cost/tests/data/0006_30-deg-right_00043.png; S=/work/wt/s5-cost
run() { name=$1; shift; PYTHONPATH=$S/src OMP_NUM_THREADS=1 /work/main/.venv/bin/python -m sdn3d.cli.edit run=/work/final_demo/runs input.image=$IMG edits=/tmp/s5data/cost/real_spec.yaml output_dir=/tmp/s5data/cost/realv_$name threads=1 overwrite=true proposals=boxes "$@" > /tmp/s5data/cost/realv_$name.log 2>&1; }
run s0 box_objects.fit.coarse_survivors=0
run fullfine box_objects.fit.fine_faces=0 box_objects.fit.fine_size=80
run c450 box_objects.fit.coarse_faces=450
run s4before box_objects.fit.coarse_survivors=0 box_objects.fit.fine_faces=0 box_objects.fit.fine_size=80 box_objects.fit.coarse_faces=450
run ffd1 box_objects.fit.ffd_step=1.0
