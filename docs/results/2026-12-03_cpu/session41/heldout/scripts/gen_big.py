# ruff: noqa: INP001, E501
"""The session-41 held-out tree: session 9's default kind (gen_t1.py) on six worlds instead of two, so that its
entries edit about three times as many distinct cars (car groups are the unit of the benchmark's intervals):
6 worlds x clone/rain x 40 frames, 25 edit and 5 occluder pairs per sequence (360 entries).
python gen_big.py OUT SEED"""
import sys
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t = time.time()
generate_dataset(SynthConfig(output_dir=sys.argv[1], seed=int(sys.argv[2]), image_size=(624, 192),
                             worlds=("0001", "0002", "0006", "0018", "0020", "0003"), variations=("clone", "rain"),
                             frames_per_sequence=40, cars_per_frame=(6, 14), edit_pairs=25, occluder_pairs=5,
                             workers=1, threads=1, overwrite=True))
print("done", time.time() - t)
