# ruff: noqa: E501, E702
"""The pose-table trees (session 10's gen_val2105.py recipe, seed and output from the command line): 40 worlds, clear
weather, 3 frames each, 5-10 cars, 624x192.  python gen_tree.py SEED OUT_DIR  (13: tuning; 2109: held-out)"""
import sys
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

seed = int(sys.argv[1]); out = sys.argv[2]
t = time.time()
generate_dataset(SynthConfig(output_dir=out, seed=seed, image_size=(624, 192), worlds=("0001", "0002", "0006", "0018", "0020") + tuple(f"{400+i:04d}" for i in range(1, 36)), variations=("clone",),
    frames_per_sequence=3, cars_per_frame=(5, 10), edit_pairs=0, occluder_pairs=0, overwrite=True, workers=1, threads=1))
print("done", time.time() - t)
