"""census.py TREE:CACHE:RAW...: frag40's proposal census (splits.py: per true car, the proposals on it, fragments,
merges of two true cars, recall, Car/Van panoptic quality) of the objects of de-rendered scenes (dbench.py's cache:
the proposals after the de-render, so after the branch's join) instead of the grouping's raw output (session 27
join40). Ground-truth instance maps (frag40's raw.py files, an oracle) only score. Frames: the cache's predicted
scenes (``meta['proposals'] == 'semantic'``). Prints splits.py's table, one row per tree and pooled.
Run from this folder: PYTHONPATH=<code>/src python census.py 37:/tmp/s27data/join40/t1/cache37br:/tmp/.../raw37.pt ...
"""
import glob
import sys

import splits
import torch


def instance_map(scene) -> torch.Tensor:
    o = scene.objects
    return (o.mask.long() * o.instance_id[:, None, None]).sum(0)


def main() -> None:
    splits.group = lambda fr, things: fr["inst"]  # the scene's objects, not a grouping of the raw outputs
    print("| tree | true cars | found (IoU >= 0.5) | PQ Car/Van (TP/FP/FN) | split cars | fragments | "
          "neighbours' spills | fragments by two peaks / 2-means split / part separation | px in fragments | "
          "px lost (no proposal) | merges | big cars (>= 1500 px) split |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    allrows, tot = [], [0.0, 0, 0, 0]
    for arg in sys.argv[1:]:
        tree, cache, rawp = arg.split(":")
        raw = torch.load(rawp, weights_only=False)
        frames = {}
        for p in glob.glob(f"{cache}/*.pt"):
            s = torch.load(p, weights_only=False)
            if s.meta.get("proposals") == "semantic" and s.meta["source"] in raw["frames"]:
                frames[s.meta["source"]] = {**raw["frames"][s.meta["source"]], "inst": instance_map(s)}
        sub = {**raw, "frames": frames}
        rows, q = splits.census(sub), splits.pq(sub)
        print(splits.summary(rows, q, f"{tree} ({len(frames)} frames)"))
        allrows += rows
        tot = [tot[0] + q[0] * (q[1] + q[2] / 2 + q[3] / 2), tot[1] + q[1], tot[2] + q[2], tot[3] + q[3]]
    denom = tot[1] + tot[2] / 2 + tot[3] / 2
    print(splits.summary(allrows, (tot[0] / max(denom, 1e-9), tot[1], tot[2], tot[3]), "pooled"))


if __name__ == "__main__":
    main()
