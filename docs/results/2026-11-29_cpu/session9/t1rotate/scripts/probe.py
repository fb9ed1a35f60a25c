# ruff: noqa: E402, E501, E701, E702
"""probe.py: cbench.py with transfer.seen_through_the_air logging how many colours each call got."""
import runpy
import sys

import sdn3d.editing.photo.transfer as T

orig = T.seen_through_the_air


def logged(defaults, colors, min_pixels=50):
    print(f"PROBE seen_through_the_air: {len(colors)} colours, {len(defaults)} defaults, {'hazed' if len(colors) >= min_pixels else 'LEFT AS THEY ARE'}", file=sys.stderr)
    return orig(defaults, colors, min_pixels)


T.seen_through_the_air = logged
sys.argv = sys.argv[1:]
runpy.run_path(sys.argv[0], run_name="__main__")
