"""One line on the machine a benchmark ran on (torch, CUDA, the GPU's name, CPU count), for a results folder's
device.txt: ``python benchmarks/device_info.py > OUT/device.txt``."""

import os

import torch

print("torch", torch.__version__, "cuda", torch.version.cuda,
      "gpu", torch.cuda.get_device_name() if torch.cuda.is_available() else "none", "cpus", os.cpu_count())
