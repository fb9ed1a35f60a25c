# ruff: noqa: E402, E501
"""A tree whose parked cars are not aligned with their lane: half of them turned by a uniform -60..60 degrees about
their own axis (the generator's layout otherwise). python gen_askew.py OUT SEED"""
import math
import sys
import time
from dataclasses import replace

import numpy as np

import sdn3d.data.synth.layout as L
from sdn3d.data.synth import SynthConfig, generate_dataset

_orig = L._sample_cars


def askew(rng, *a, **k):
    tracks = _orig(rng, *a, **k)
    n = len(tracks.yaw)
    if n == 0:
        return tracks
    local = np.random.default_rng(int(rng.integers(0, 2**31)))
    parked = tracks.speed == 0
    turn = (local.uniform(size=n) < 0.5) & parked
    yaw = tracks.yaw + np.where(turn, local.uniform(-math.radians(60), math.radians(60), size=n), 0.0)
    return replace(tracks, yaw=yaw)


L._sample_cars = askew
t = time.time()
generate_dataset(SynthConfig(output_dir=sys.argv[1], seed=int(sys.argv[2]), image_size=(624, 192),
                             worlds=("0001", "0002"), variations=("clone", "rain"), frames_per_sequence=40,
                             cars_per_frame=(6, 14), edit_pairs=0, occluder_pairs=0, workers=1, threads=1,
                             overwrite=True))
print("done", time.time() - t)
