# ruff: noqa: INP001, E402
"""Run sdn3d-edit or sdn3d-bench with PhotoSettings defaults replaced, for settings their configs do not expose
(e.g. predicted_example_erode with the patch applied):
    PHOTO='name=value,...' python patched_cli.py edit|bench OVERRIDES..."""
import importlib
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
program = sys.argv[1]
main = importlib.import_module(f"sdn3d.cli.{program}").main
sys.argv = [f"sdn3d-{program}", *sys.argv[2:]]
main()
