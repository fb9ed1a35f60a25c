# ruff: noqa: E402, E501, E701, E702
"""cmpcap.py A.pt B.pt: cars (frame, ground-truth id) whose flip (fitted yaw over 90 degrees off the truth, oracle
geometry for scoring) differs between two captures, with both lamp readings and the mask IoU."""
import math
import sys

import torch


def err(a, b): return abs(math.degrees(math.atan2(math.sin(a - b), math.cos(a - b))))
A = {(r["key"], r["gt_id"]): r for r in torch.load(sys.argv[1], weights_only=False)}
B = {(r["key"], r["gt_id"]): r for r in torch.load(sys.argv[2], weights_only=False)}
for k in sorted(set(A) & set(B)):
    a, b = A[k], B[k]; ea, eb = err(a["fit_ry"], a["true_ry"]), err(b["fit_ry"], b["true_ry"])
    if (ea > 90) != (eb > 90):
        def f(r): return f"lamp p{int(r.get('lamp_present', -1))} u{int(r.get('lamp_usable', -1))} off {float(r.get('lamp_offset', 0)):+.2f} front p{int(r.get('front_present', -1))} u{int(r.get('front_usable', -1))}"
        print(k, f"iou {a['iou']:.2f} err {ea:5.1f} -> {eb:5.1f} | A {f(a)} | B {f(b)} | net err {err(float(b.get('net_ry', 0)), b['true_ry']):.0f}")
