# ruff: noqa: E501
"""The held-out tree of seed 2089: /tmp/s3data/gen_val13.py with seed 2089 and its own output directory (written by
held.sh with sed; this is that file, tidied for ruff)."""
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t = time.time()
generate_dataset(SynthConfig(output_dir="/tmp/s8data/editcall/val2089", seed=2089, image_size=(624, 192), worlds=("0001", "0002", "0006", "0018", "0020") + tuple(f"{400 + i:04d}" for i in range(1, 36)), variations=("clone",),
    frames_per_sequence=3, cars_per_frame=(5, 10), edit_pairs=0, occluder_pairs=0, overwrite=True, workers=1, threads=1))
print("done", time.time() - t)
