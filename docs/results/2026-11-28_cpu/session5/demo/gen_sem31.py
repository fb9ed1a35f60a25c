# ruff: noqa: E501
"""Tuning tree for the semantic branch's proposals on clone and rain (session 5, demo): seed 31, 8 worlds x [clone, rain] x 6 frames."""
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t = time.time()
worlds = ("0001", "0002", "0006", "0018", "0020") + tuple(f"{600 + i:04d}" for i in range(1, 4))
generate_dataset(SynthConfig(output_dir="/tmp/s5data/demo/sem31", seed=31, image_size=(624, 192), worlds=worlds,
                             variations=("clone", "rain"), frames_per_sequence=6, cars_per_frame=(5, 10), edit_pairs=0,
                             occluder_pairs=0, overwrite=True, workers=1, threads=1))
print("done", time.time() - t)
