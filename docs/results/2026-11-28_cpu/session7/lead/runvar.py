# ruff: noqa
"""runvar.py VARIANT bench-args...: the bench with a transfer variant (nopart: no reflection change on part-sourced pixels; glass: glass only)"""
import sys
import sdn3d.editing.photo.transfer as T
from sdn3d.meshes.parts import Part
v = sys.argv.pop(1)
if "nopart" in v:
    orig = T._part_colors
    def w(*a):
        a = list(a); a[10] = 0.0; return orig(*a)
    T._part_colors = w
if "glass" in v:
    T.REFLECTIVE_PARTS = (int(Part.GLASS),)
if "p3" in v:
    import sdn3d.editing.photo.light as L
    L.REFLECTION_POWER = 3.0
from sdn3d.cli.bench import main
main()
