# ruff: noqa: E402, E501, E701, E702
import time

from sdn3d.data.synth import SynthConfig, generate_dataset

t=time.time()
generate_dataset(SynthConfig(output_dir="/tmp/s10data/editcall/val2105", seed=2105, image_size=(624,192), worlds=("0001","0002","0006","0018","0020")+tuple(f"{400+i:04d}" for i in range(1, 36)), variations=("clone",),
    frames_per_sequence=3, cars_per_frame=(5,10), edit_pairs=0, occluder_pairs=0, overwrite=True, workers=1, threads=1))
print("done", time.time()-t)
