"""The held-out pose tree of session 6, poses (seed 2071; generated once, after the code was final): 40 worlds x clone x
3 frames, 5-10 cars a frame, 624x192 (the style of session 4's gen_pose2051.py)."""
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t = time.time()
worlds = ("0001", "0002", "0006", "0018", "0020") + tuple(f"{700 + i:04d}" for i in range(1, 36))
generate_dataset(SynthConfig(output_dir="/tmp/s6data/poses/pose2071", seed=2071, image_size=(624, 192), worlds=worlds,
                             variations=("clone",), frames_per_sequence=3, cars_per_frame=(5, 10), edit_pairs=0,
                             occluder_pairs=0, overwrite=True, workers=1, threads=1))
print("done", time.time() - t)
