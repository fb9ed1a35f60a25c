# ruff: noqa: INP001, E501
"""Cut a counterfactual.json to what analyze.py reads (info, the pairs' keys, metrics, references and errors; values
rounded to 5 decimals; the summary and comparisons are in counterfactual.md): python slim.py IN.json OUT.json.gz"""
import gzip
import json
import sys


def r(x):
    if isinstance(x, float):
        return round(x, 5) if x == x else None
    if isinstance(x, dict):
        return {k: r(v) for k, v in x.items()}
    if isinstance(x, list):
        return [r(v) for v in x]
    return x


d = json.load(open(sys.argv[1]))
keep = ("key", "source", "bin", "kind", "car", "iou", "metrics", "reference", "errors")
out = {"info": d["info"], "pairs": [r({k: p[k] for k in keep if k in p}) for p in d["pairs"]]}
with gzip.open(sys.argv[2], "wt") as f:
    json.dump(out, f, separators=(",", ":"))
