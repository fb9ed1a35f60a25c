# ruff: noqa: E501
"""gen_pairs.py OUT SEED WORLDS VARIATIONS CARS FRAMES: delete-only counterfactual trees (no turns) for the learnt
fill's training and validation data; seeds 300-399 only (neither tuning nor held-out)."""
import sys
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t = time.time()
out, seed, worlds, variations, cars, frames = sys.argv[1], int(sys.argv[2]), tuple(sys.argv[3].split(",")), tuple(sys.argv[4].split(",")), int(sys.argv[5]), int(sys.argv[6])
assert 300 <= seed <= 399, "training and validation seeds are 300-399"
generate_dataset(SynthConfig(output_dir=out, seed=seed, image_size=(624, 192), worlds=worlds, variations=variations,
                             frames_per_sequence=frames, edit_pairs=0, occluder_pairs=0, workers=1, threads=1,
                             counterfactual_cars=cars, counterfactual_turns=(), counterfactual_delete=True, overwrite=True))
print("done", time.time() - t)
