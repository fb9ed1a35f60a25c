# ruff: noqa: E501
"""diag_cf.py TREE OUT SOURCE: sdn3d-bench's counterfactual turn pairs (fill rays) on TREE, source scene SOURCE
(oracle: ground-truth geometry; semantic: predicted, w28), in-process with facets.py's hooks: prints the facet steps
pooled over every turned pair's render (facets.steps: one smooth template panel's never-seen pixels, mean |dRGB| x 255
across a face edge and within a face). Run with the code under test on PYTHONPATH (cwd: its tree)."""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import facets  # noqa: E402

from sdn3d.cli import bench  # noqa: E402

facets.install(accumulate=True)
TREE, OUT, SOURCE = sys.argv[1:4]
W = "/tmp/s28/demo2/outputs/demo/runs"
ck = [f"checkpoints.semantic={W}/semantic/checkpoints/inference.pt", f"checkpoints.geometric={W}/geometric/checkpoints/inference.pt"] if SOURCE == "semantic" else []
rc = bench.main(["counterfactual=true", f"data.root={TREE}", f"output_dir={OUT}", "examples=0", "threads=1", "counterfactual_kinds=[turn]",
                 f"counterfactual_sources=[{SOURCE}]", "counterfactual_fills=[rays]", *ck, *sys.argv[4:]])
a, na, w, nw = facets.totals
print(json.dumps({"rc": rc, "tree": TREE, "source": SOURCE, "across a face edge": round(a / max(na, 1), 2), "pairs": na,
                  "within a face": round(w / max(nw, 1), 2), "pairs within": nw, "ratio": round((a / max(na, 1)) / max(w / max(nw, 1), 1e-9), 2)}))
