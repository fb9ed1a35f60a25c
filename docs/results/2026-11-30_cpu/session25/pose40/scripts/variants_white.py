"""variants_white.py WHITE.pt...: how often the red bodies' headlight test finds headlights on front views and on
back views (the truth an oracle, read only to score), on ground-truth masks (an oracle) and on proposals, for
variants of which near-white pixels count (screen_white.py's saves):

- ``main``: every near-white lower-half pixel (main's white_lamps), at least white_min_share of the mask;
- ``run>=k``: only pixels in a horizontal run of at least k near-white pixels (a lamp is wider than tall; a rain
  streak is a one-pixel vertical line);
- ``enclosed``: only pixels with red body pixels both left and right of them on their row (a headlight sits in
  the body; a lane marking or the road the mask spills onto lies beside it);
- combinations.

    python variants_white.py /tmp/s25data/pose40/white_35.pt ...
"""
import sys
from collections import defaultdict

import torch
import torch.nn.functional as F


def runs(white: torch.Tensor, k: int) -> torch.Tensor:
    """``(S, S)`` bool: the pixels of ``white`` in a horizontal run of at least ``k`` of them."""
    if k <= 1:
        return white
    w = white.float()[None, None]
    full = F.pad(F.avg_pool2d(w, (1, k), stride=1).eq(1).float(), (k - 1, k - 1))  # windows all white
    return white & F.max_pool2d(full, (1, k), stride=1)[0, 0].bool()


def enclosed(white: torch.Tensor, red: torch.Tensor) -> torch.Tensor:
    """``(S, S)`` bool: the pixels of ``white`` with a red pixel left and right of them on their row."""
    left = red.int().cummax(1).values.bool()
    right = red.flip(1).int().cummax(1).values.flip(1).bool()
    return white & left & right


def present(white: torch.Tensor, sure: torch.Tensor, share: float = 0.001) -> bool:
    n = int(white.sum())
    return n > 0 and n >= share * int(sure.sum())


VARIANTS = {
    "main": lambda s: s["white"],
    "run>=2": lambda s: runs(s["white"], 2),
    "run>=3": lambda s: runs(s["white"], 3),
    "enclosed": lambda s: enclosed(s["white"], s["red"]),
    "enclosed+run>=2": lambda s: runs(enclosed(s["white"], s["red"]), 2),
    "enclosed+run>=3": lambda s: runs(enclosed(s["white"], s["red"]), 3),
}


def main() -> None:
    saved = [s for p in sys.argv[1:] for s in torch.load(p)]
    saved = [s for s in saved if s["share_red"] > 0.12]  # red bodies (the red cue unusable by its share)
    print(f"{len(saved)} red-bodied readings ({sum(s['front'] for s in saved)} front views)")
    print("variant            | oracle: fronts with headlights, backs with | proposals: fronts with, backs with")
    for name, rule in VARIANTS.items():
        c = defaultdict(lambda: [0, 0])
        for s in saved:
            key = (s["mask"], s["front"])
            c[key][0] += present(rule(s), s["sure"])
            c[key][1] += 1
        cells = [f"{c[(m, f)][0]:3d}/{c[(m, f)][1]:3d}" for m in ("oracle", "proposal") for f in (True, False)]
        print(f"{name:18} | {cells[0]}  {cells[1]} | {cells[2]}  {cells[3]}")


if __name__ == "__main__":
    main()
