# ruff: noqa
"""gen_rot.py OUT SEED: counterfactual delete pairs on rotated cameras (30-deg-right, 15-deg-left, 30-deg-left)."""
import sys, time
from sdn3d.data.synth import SynthConfig, generate_dataset
t = time.time()
generate_dataset(SynthConfig(output_dir=sys.argv[1], seed=int(sys.argv[2]), image_size=(624, 192), worlds=("0001", "0002"),
                             variations=tuple(sys.argv[3].split(",")) if len(sys.argv) > 3 else ("30-deg-right", "15-deg-left", "30-deg-left"), frames_per_sequence=30, edit_pairs=0,
                             occluder_pairs=0, workers=1, threads=1, counterfactual_cars=8, counterfactual_turns=(),
                             counterfactual_delete=True, overwrite=True))
print("done", time.time() - t)
