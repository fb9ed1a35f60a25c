# ruff: noqa: E401, E501
"""gen_train.py OUT SEED [VARIATIONS]: delete-only counterfactual pairs for training the learnt fill (seeds 300-399 only)."""
import sys
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t = time.time()
seed = int(sys.argv[2])
assert 300 <= seed <= 399, "training seeds are 300-399"
generate_dataset(SynthConfig(output_dir=sys.argv[1], seed=seed, image_size=(624, 192),
                             worlds=("0001", "0002", "0006", "0018", "0020"),
                             variations=tuple(sys.argv[3].split(",")) if len(sys.argv) > 3 else ("clone", "fog", "30-deg-right", "15-deg-left"), frames_per_sequence=10,
                             edit_pairs=0, occluder_pairs=0, workers=1, threads=1, counterfactual_cars=6,
                             counterfactual_turns=(), counterfactual_delete=True, overwrite=True))
print("done", time.time() - t)
