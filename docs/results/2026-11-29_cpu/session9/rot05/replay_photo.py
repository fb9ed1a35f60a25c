# ruff: noqa: E402, E501, E701, E702
"""replay_photo.py OUT [--lat DATA] [--cap DIR ...] [--only NAME_PREFIX]: draws every edit of the latency tree DATA
(photo_latency.py's cases, fill='rays', fresh source state) and every render_photo call captured by capture_bench.py
in DIR with the code on PYTHONPATH, and saves each picture, source map and part map (OUT/<name>.npz, with the result's
summary as JSON); compare_replays.py compares two such folders.

    compare: replay_photo.py --compare A B   (bit identity per picture; else max abs difference and PSNR to A)"""
import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np
import torch

torch.set_num_threads(1)


def lat_cases(data):
    sys.path.insert(0, str(Path(__file__).parent))
    from prof import cases

    from sdn3d.editing.photo.settings import PhotoSettings
    cs, frame = cases(data)
    for i, (kind, scene, edited, original) in enumerate(cs):
        yield f"lat_{i:02d}_{kind}", dict(original=original, transform=frame, scene=scene, edited=edited,
                                          settings=PhotoSettings(fill="rays"), recolor=None, generated=None)


def cap_cases(folder):
    folder = Path(folder)
    for p in sorted(folder.glob("*.pt")):
        yield f"{folder.name}_{p.stem}", torch.load(p, weights_only=False)


def draw(args, out):
    from sdn3d.editing.photo.transfer import render_photo
    out.mkdir(parents=True, exist_ok=True)
    gens = ([lat_cases(args.lat)] if args.lat else []) + [cap_cases(c) for c in args.cap]
    cpu = {}
    for gen in gens:
        for name, a in gen:
            if args.only and not name.startswith(args.only): continue
            c0 = time.process_time()
            r = render_photo(a["original"], a["transform"], a["scene"], a["edited"], None, a["settings"], a["recolor"],
                             a["generated"])
            cpu[name] = 1000 * (time.process_time() - c0)
            np.savez_compressed(out / f"{name}.npz", image=r.image.numpy(), source=r.source.numpy(),
                                parts=r.parts.numpy(), summary=np.array(json.dumps(r.summary(), sort_keys=True)))
            print(name, f"{cpu[name]:.0f} ms", flush=True)
    (out / "cpu_ms.json").write_text(json.dumps(cpu, indent=1))


def compare(a, b):
    """bit identity per picture; per set (name prefix) the max and mean |difference| of the pictures (0-1 scale, all
    pixels and channels) and of the pixels that differ, and the worst pictures."""
    names = sorted(p.name for p in Path(a).glob("*.npz"))
    same = 0; worst = []; sets = {}
    for n in names:
        pb = Path(b) / n
        if not pb.exists(): print("missing in B:", n); continue
        x, y = np.load(Path(a) / n), np.load(pb)
        diff = {k: not np.array_equal(x[k], y[k]) for k in ("image", "source", "parts", "summary")}
        xi, yi = x["image"].astype(np.float64), y["image"].astype(np.float64)
        scale = 255.0 if x["image"].dtype == np.uint8 else 1.0
        d = np.abs(xi - yi) / scale
        st = sets.setdefault(n.rsplit("_", 1)[0] if not n.startswith("lat_") else "lat3", dict(n=0, same=0, max=0.0, mean=[], changed_px=0, changed_sum=0.0))
        st["n"] += 1; st["max"] = max(st["max"], float(d.max())); st["mean"].append(float(d.mean()))
        px = d.max(0) > 0; st["changed_px"] += int(px.sum()); st["changed_sum"] += float(d.max(0)[px].sum())
        if not any(diff.values()): same += 1; st["same"] += 1; continue
        mse = float(((xi - yi) ** 2).mean()) / scale ** 2
        psnr = 10 * math.log10(1 / mse) if mse > 0 else math.inf
        worst.append((n, diff, float(d.max()), float(d.mean()), psnr, int((x["source"] != y["source"]).sum())))
    print(f"{same}/{len(names)} bit-identical (image, source map, part map, summary)")
    print("| set | pictures | bit-identical | max abs diff | mean abs diff (all pixels) | pixels changed per picture | mean max-channel diff of changed pixels |")
    print("|---|---|---|---|---|---|---|")
    for k, st in sets.items():
        cp = st["changed_px"]
        print(f"| {k} | {st['n']} | {st['same']} | {st['max']:.4f} | {np.mean(st['mean']):.2e} | {cp / st['n']:.1f} | {(st['changed_sum'] / cp if cp else 0):.4f} |")
    for n, d, mad, mean, psnr, ns in sorted(worst, key=lambda w: -w[3])[:12]:
        print(f"  {n}: differs in {[k for k, v in d.items() if v]}; max abs diff {mad:.4f}, mean abs diff {mean:.2e}, PSNR B vs A {psnr:.2f} dB, source-map pixels differing {ns}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("out", nargs="?")
    ap.add_argument("--lat"); ap.add_argument("--cap", nargs="*", default=[]); ap.add_argument("--only")
    ap.add_argument("--compare", nargs=2)
    args = ap.parse_args()
    if args.compare: compare(*args.compare)
    else: draw(args, Path(args.out))
