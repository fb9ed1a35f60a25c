# ruff: noqa: INP001
"""gen.py OUT: the demo's synthetic recipe (conf/demo.yaml's synth, seed 0) with 3x the frames per sequence."""
import sys

from omegaconf import OmegaConf

from sdn3d.data.synth import SynthConfig, generate_dataset

demo = OmegaConf.load("/work/main/conf/demo.yaml")
synth = OmegaConf.to_container(demo.synth, resolve=True)
synth["frames_per_sequence"] = 48
generate_dataset(SynthConfig(output_dir=sys.argv[1], seed=0, overwrite=True, threads=1, **synth))
