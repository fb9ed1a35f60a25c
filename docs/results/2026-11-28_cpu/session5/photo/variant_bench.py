"""cached_bench with transfer.SHADOW_GROUND from the SG environment variable (tuning only)."""
import os

import sdn3d.editing.photo.transfer as tr

if "SG" in os.environ:
    tr.SHADOW_GROUND = float(os.environ["SG"])
exec(open("/tmp/s5data/lead/cached_bench.py").read())
