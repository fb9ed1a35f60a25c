# ruff: noqa: E402, E501, E701, E702
"""diag_real.py OUT [OVERRIDE ...]: sdn3d-edit on the real frame (tests/data/0006_30-deg-right_00043.png, the editor
shots' two boxes, w31), both cars turned -90 degrees (real_spec.yaml beside this script), with facets.py's hooks: prints
the drawn pixels' source-code shares and the facet steps (facets.steps: one smooth template panel's never-seen pixels,
mean |dRGB| x 255 across a face edge and within a face). Run with the code under test on PYTHONPATH."""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import belt  # noqa: E402
import facets  # noqa: E402
import numpy as np  # noqa: E402

from sdn3d.cli import edit  # noqa: E402
from sdn3d.editing.photo.settings import SOURCE_NAMES  # noqa: E402

facets.install()
OUT = sys.argv[1]
rc = edit.main(["input.image=/work/main/tests/data/0006_30-deg-right_00043.png", f"edits={HERE}/real_spec.yaml",
                "run=/tmp/s31/ci/outputs/demo/runs", "proposals=boxes", "threads=1", "diagnostics=true", f"output_dir={OUT}",
                "progress=false", *sys.argv[2:]])
res = facets.last["result"]
pix, f, m, n = facets.last["draw"]
codes = res.source.numpy().reshape(-1)
np.savez_compressed(f"{OUT}/diag_maps.npz", parts=res.parts.numpy(), source=res.source.numpy(), pix=pix.numpy(), face=f.numpy(), mesh=m.numpy())
drawn = {}
for mesh in m.unique().tolist():
    c = codes[pix[m == mesh].numpy()]
    drawn[f"mesh {mesh}"] = {"drawn pixels": int(len(c)), **{SOURCE_NAMES[k]: round(float((c == k).mean()), 3) for k in np.unique(c)}}


def table(across, na, within, nw):
    return {"across a face edge": round(across / max(na, 1), 2), "pairs": na, "within a face": round(within / max(nw, 1), 2),
            "pairs within": nw, "ratio": round((across / max(na, 1)) / max(within / max(nw, 1), 1e-9), 2)}


print(json.dumps({"rc": rc, "codes of the pixels the turned cars won": drawn,
                  "facet steps (one smooth panel, never-seen pixels)": table(*facets.steps()),
                  **{f"facet steps, mesh {mesh} alone": table(*facets.steps(mesh)) for mesh in m.unique().tolist()},
                  **{f"belt line, mesh {mesh} (x {int((pix[m == mesh] % res.image.shape[-1]).float().mean())})": belt.belt(res, pix, m, mesh)
                     for mesh in m.unique().tolist()}}, indent=1))
