# ruff: noqa: E501
"""Candidate demo data trees (seed 0, the demo's own seed) for the geometric/semantic choice of session 5."""
import sys
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

name = sys.argv[1]
C = {
    "c8": dict(worlds=("0001", "0002", "0006", "0018", "0020", "0003", "0004", "0005"), variations=("clone", "rain"),
               frames_per_sequence=16, edit_pairs=1, occluder_pairs=0),
    "c4": dict(worlds=("0001", "0002", "0006", "0018"), variations=("clone", "rain"),
               frames_per_sequence=32, edit_pairs=1, occluder_pairs=1),
    "c16": dict(worlds=tuple(f"{i:04d}" for i in (1, 2, 6, 18, 20, 3, 4, 5, 7, 8, 9, 10, 11, 12, 13, 14)),
                variations=("clone", "rain"), frames_per_sequence=8, edit_pairs=1, occluder_pairs=0),
    # the geometric branch's own set: many worlds, few frames each (tunebig's variety, the demo's seed)
    "geo32x6": dict(worlds=tuple(f"{i:04d}" for i in range(101, 133)), variations=("clone", "rain"),
                    frames_per_sequence=6, edit_pairs=0, occluder_pairs=0),
    "geo32x6c": dict(worlds=tuple(f"{i:04d}" for i in range(101, 133)), variations=("clone",),
                     frames_per_sequence=6, edit_pairs=0, occluder_pairs=0),
}[name]
t = time.time()
c0 = time.process_time()
generate_dataset(SynthConfig(output_dir=f"/tmp/s5data/demo/{name}", seed=0, image_size=(624, 192), cars_per_frame=(5, 10),
                             max_edit_operations=3, overwrite=True, workers=2, threads=1, **C))
print("done wall", time.time() - t, "cpu(parent)", time.process_time() - c0)
