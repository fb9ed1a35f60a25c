# ruff: noqa
"""runvar.py VARIANT bench-args...: the bench with a lamp variant: head=R,G,B (LAMP_DEFAULTS head lamp colour) or band=LO,HI"""
import sys
import sdn3d.editing.photo.transfer as T
from sdn3d.meshes.parts import Part
v = sys.argv.pop(1)
for item in v.split(";"):
    k, val = item.split("=")
    if k == "head":
        T.LAMP_DEFAULTS[int(Part.FRONT_LIGHTS)] = tuple(float(x) for x in val.split(","))
    if k == "tail":
        T.LAMP_DEFAULTS[int(Part.TAIL_LIGHTS)] = tuple(float(x) for x in val.split(","))
    if k == "band":
        T.LAMP_BAND = tuple(float(x) for x in val.split(","))
from sdn3d.cli.bench import main
main()
