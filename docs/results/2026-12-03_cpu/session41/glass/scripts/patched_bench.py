# ruff: noqa: INP001, E402
"""Run sdn3d-bench with PhotoSettings defaults replaced: PHOTO='name=value,...' python patched_bench.py OVERRIDES...
(for settings the bench config does not expose, e.g. predicted_example_erode with the patch applied)."""
import inspect
import os
import sys

from sdn3d.editing.photo.settings import PhotoSettings

over = dict(kv.split("=") for kv in os.environ.get("PHOTO", "").split(",") if kv)
params = list(inspect.signature(PhotoSettings.__init__).parameters.values())[1:]
defaults = list(PhotoSettings.__init__.__defaults__)
names = [p.name for p in params if p.default is not inspect.Parameter.empty]
for k, v in over.items():
    i = names.index(k)
    old = defaults[i]
    defaults[i] = type(old)(v) if old is not None else int(v)
PhotoSettings.__init__.__defaults__ = tuple(defaults)
print("photo defaults:", over, file=sys.stderr)
from sdn3d.cli.bench import main

sys.argv = ["sdn3d-bench", *sys.argv[1:]]
main()
