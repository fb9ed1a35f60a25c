# ruff: noqa: INP001, E501
"""timed_edit.py ARGS...: sdn3d-edit with ARGS (its own "photo N ms" line printed as usual), and after it the photo
stage's CPU time of the process (user and system: less swayed by others' load on a shared machine than its wall time)
as "photo cpu N ms"."""
import sys
import time

from sdn3d.cli import edit
from sdn3d.editing import appearance

draw = appearance.PhotoRenderer.draw
spent: list[float] = []


def timed(self, *args, **kwargs):
    c0 = time.process_time()
    try:
        return draw(self, *args, **kwargs)
    finally:
        spent.append(1000 * (time.process_time() - c0))


appearance.PhotoRenderer.draw = timed
edit.main(sys.argv[1:])
print(f"photo cpu {sum(spent):.0f} ms", file=sys.stderr)
