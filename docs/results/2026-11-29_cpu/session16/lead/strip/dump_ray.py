# ruff: noqa: E402, E501, E702, I001, B905
"""Run the real frame's black-car delete (sdn3d-edit, boxes) and save ray_fill's inputs."""
import sys
import torch
import sdn3d.editing.photo.road as fill
orig = fill.ray_fill
def wrapped(*a, **k):
    torch.save({'args': a, 'kwargs': {kk: v for kk, v in k.items()}}, '/tmp/s16data/lead/strip/ray_inputs.pt')
    return orig(*a, **k)
fill.ray_fill = wrapped
from sdn3d.cli.edit import main
sys.argv = ['sdn3d-edit'] + sys.argv[1:]
main()
