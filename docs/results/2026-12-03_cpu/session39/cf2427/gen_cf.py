# ruff: noqa: INP001, E501
"""Counterfactual trees (session 5 turns's gen_cf.py, unchanged): python gen_cf.py OUT SEED WORLDS(comma) CARS; run with
main's src on PYTHONPATH, OMP_NUM_THREADS=1."""
import sys
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t = time.time()
out, seed, worlds, cars = sys.argv[1], int(sys.argv[2]), tuple(sys.argv[3].split(",")), int(sys.argv[4])
generate_dataset(SynthConfig(output_dir=out, seed=seed, image_size=(624, 192), worlds=worlds,
                             variations=("clone", "fog"), frames_per_sequence=30, edit_pairs=0, occluder_pairs=0,
                             workers=1, threads=1, counterfactual_cars=cars, counterfactual_turns=(15, 45, 90, 180),
                             overwrite=True))
print("done", time.time() - t)
