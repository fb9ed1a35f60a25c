# ruff: noqa: E402, E501, E701, E702
"""Table 1 trees for session 4 (120 entries: 2 worlds x clone/rain x 40 frames, 25 edit and 5 occluder pairs each):
python gen_t1.py OUT SEED"""
import sys
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t = time.time()
generate_dataset(SynthConfig(output_dir=sys.argv[1], seed=int(sys.argv[2]), image_size=(624, 192),
                             worlds=("0001", "0002"), variations=("clone", "rain"), frames_per_sequence=40,
                             cars_per_frame=(6, 14), edit_pairs=25, occluder_pairs=5, workers=1, threads=1,
                             overwrite=True))
print("done", time.time() - t)
