# ruff: noqa: E401, E501, F401, I001
import sys, time
from sdn3d.data.synth import SynthConfig, generate_dataset
t = time.time()
generate_dataset(SynthConfig(output_dir="/tmp/s12data/realframe/held/rc2119", seed=2119, image_size=(624, 192),
                             worlds=("0001", "0002", "0006", "0018", "0020") + tuple(f"{400+i:04d}" for i in range(1, 11)),
                             variations=("clone", "fog", "rain"), frames_per_sequence=2, cars_per_frame=(5, 10),
                             edit_pairs=0, occluder_pairs=0, overwrite=True, workers=1, threads=1))
print("done", time.time() - t)
