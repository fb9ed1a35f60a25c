"""variants_white.py WHITE.pt...: how often the red bodies' headlight test finds headlights on front views and on
back views (the truth an oracle, read only to score), on ground-truth masks (an oracle) and on proposals, for
variants of which near-white pixels count (screen_white.py's saves):

- ``main``: every near-white lower-half pixel (main's white_lamps), at least white_min_share of the mask;
- ``run>=k``: only pixels in a horizontal run of at least k near-white pixels (a lamp is wider than tall; a rain
  streak is a one-pixel vertical line);
- ``enclosed``: only pixels with red body pixels both left and right of them on their row (a headlight sits in
  the body; a lane marking or the road the mask spills onto lies beside it);
- ``bounded``: only runs of near-white pixels ended on each side by red or by the mask's edge, red on one side;
- ``near red k``: only pixels within k pixels of a red one on their row;
- ``span rows r``: only pixels between the leftmost and the rightmost red pixel of the rows within r of theirs (the
  branch's rule, ``lamps.in_the_body``; r = 2 at 64-px crops, ``LampCue.headlight_rows`` 0.03);
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


def bounded(white: torch.Tensor, red: torch.Tensor, mask: torch.Tensor) -> torch.Tensor:
    """``(S, S)`` bool: the pixels of ``white`` whose run of white pixels on their row ends, on each side, at a red
    pixel or past the mask (its edge), and at a red one on at least one side: a lamp in the body or at its edge, not a
    marking on the road a mask spills onto (bounded by road pixels)."""
    w = white.shape[1]
    cols = torch.arange(w).expand_as(white)
    kind = torch.where(red, 1, torch.where(mask, 0, 2))  # 1 red, 2 past the mask, 0 anything else in the mask
    kind = torch.cat([torch.full_like(kind[:, :1], 2), kind, torch.full_like(kind[:, :1], 2)], 1)  # crop edge: past
    left = torch.where(~white, cols, -1).cummax(1).values + 1  # padded index of the last non-white at or left of j
    right = torch.where(~white, cols, w).flip(1).cummin(1).values.flip(1) + 1
    lk, rk = kind.gather(1, left), kind.gather(1, right)
    return white & (lk > 0) & (rk > 0) & ((lk == 1) | (rk == 1))


def near_red(white: torch.Tensor, red: torch.Tensor, k: int) -> torch.Tensor:
    """``(S, S)`` bool: the pixels of ``white`` within ``k`` pixels of a red one on their row."""
    grown = F.max_pool2d(red.float()[None, None], (1, 2 * k + 1), stride=1, padding=(0, k))[0, 0].bool()
    return white & grown


def in_span(white: torch.Tensor, red: torch.Tensor, r: int) -> torch.Tensor:
    """``(S, S)`` bool: the pixels of ``white`` between the leftmost and the rightmost red pixel of the rows within
    ``r`` of theirs (the body's extent near their height: a corner headlight has the bumper or bonnet beside it)."""
    s = white.shape[1]
    cols = torch.arange(s, dtype=torch.float32).expand_as(white)
    left = torch.where(red, cols, torch.full_like(cols, s)).amin(1)  # (S,) per row
    right = torch.where(red, cols, torch.full_like(cols, -1)).amax(1)
    lo = -F.max_pool1d(-left[None, None], 2 * r + 1, stride=1, padding=r)[0, 0]
    hi = F.max_pool1d(right[None, None], 2 * r + 1, stride=1, padding=r)[0, 0]
    return white & (cols >= lo[:, None]) & (cols <= hi[:, None])


def present(white: torch.Tensor, sure: torch.Tensor, share: float = 0.001) -> bool:
    n = int(white.sum())
    return n > 0 and n >= share * int(sure.sum())


VARIANTS = {
    "main": lambda s: s["white"],
    "run>=2": lambda s: runs(s["white"], 2),
    "run>=3": lambda s: runs(s["white"], 3),
    "enclosed": lambda s: enclosed(s["white"], s["red"]),
    "bounded": lambda s: bounded(s["white"], s["red"], s["sure"]),
    "near red 1": lambda s: near_red(s["white"], s["red"], 1),
    "near red 2": lambda s: near_red(s["white"], s["red"], 2),
    "near red 3": lambda s: near_red(s["white"], s["red"], 3),
    "near red 5": lambda s: near_red(s["white"], s["red"], 5),
    "span rows 1": lambda s: in_span(s["white"], s["red"], 1),
    "span rows 2": lambda s: in_span(s["white"], s["red"], 2),
    "span rows 3": lambda s: in_span(s["white"], s["red"], 3),
    "span rows 4": lambda s: in_span(s["white"], s["red"], 4),
    "span rows 8": lambda s: in_span(s["white"], s["red"], 8),
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
