# ruff: noqa: E501
"""v13tab.py JSON...: the val13 pose table's rows (all worlds) side by side."""
import json
import sys

for f in sys.argv[1:]:
    t = json.load(open(f))["table"]
    for row, v in t.items():
        a = v.get("all", v)
        print(f"{f.split('/')[-1]:14s} {row:42s} " + " ".join(f"{k}={a[k]}" for k in a if not isinstance(a[k], (dict, list))))
