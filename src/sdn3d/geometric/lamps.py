"""Front from back by the lamps (issue 40): red tail lights mark a vehicle's back.

A silhouette hardly tells a car's front from its back, and a geometric branch trained for a few CPU minutes has
not yet learnt to (it guesses the facing from context). The tail lights are red and the headlights are not, so the
red lamp pixels of the masked object crop say which end the camera sees:

- ``red`` pixels: ``r > red_min``, ``r > ratio * g`` and ``r > ratio * b`` (saturated red), inside the mask;
- usable when there are at least ``min_pixels`` of them and at most ``max_share`` of the mask (a red car's body
  is red all over: no cue), they lie in one band (the standard deviation of their rows at most ``max_row_spread``
  of the mask's height: lamps sit at one height, a red texture or noise does not), and the object's crop has at
  least ``min_mask`` mask pixels (small cars: no lamps seen);
- for a local orientation (observation angle) ``alpha = ry - ray`` the back end faces the camera where
  ``sin(alpha) < 0`` (``alpha = -pi/2``: seen from behind) and lies towards ``-cos(alpha)`` across the image
  (``alpha = 0``: the front points right, the back is left). The evidence for ``alpha`` is
  ``-(sin(alpha) + 2 d cos(alpha))`` with ``d`` the red pixels' mean column offset from the mask's, over the box
  width: +1 for a back view with red lamps, -1 for the reversed hypothesis. Without red lamps on a large enough
  object the front is more likely seen: ``absent_weight * sin(alpha)``. On a seed-13 tuning tree (442 cars and
  vans on ground-truth masks, issue 40) every usable crop with red lamps showed its back (160 of 160) and 220 of the
  233 usable crops without showed their front (10 of the 13 others cut by the image border, their lamps outside
  it): an absence is nearly as sure as a presence. With ``absent_weight = 0.3`` it never reached ``flip_below``
  and the branch's front/back stood (42 flips); from 0.5 to 1.0 an absence turns a back view end for end
  (17 flips); 0.5 is the default.

A red body defeats the red cue (its red share is over ``max_share``). There the headlights speak instead
(:func:`white_lamps`): near-white pixels (every channel over ``white_min``, channels within ``white_spread`` of
each other) in the lower half of the mask, the lamps' and the grille's height (the roof and glass reflect white
too), at least ``white_min_share`` of the mask: the front is seen, and lies towards ``+cos(alpha)`` (their
offset ``d``): evidence ``sin(alpha) + 2 d cos(alpha)``; none: the back is more likely seen, ``-absent_weight *
sin(alpha)``. On the seed-13 tuning tree's 48 red-bodied cars and vans (16 vehicles, 3 frames each; the branch's
crops) such pixels were on 15 of the 18 front views and on none of the 30 back views (``white_min`` 0.6 or
``white_min_share`` 0.002: 12 to 14 fronts; 0.5: 4 to 13 backs too); ``red_body``: false turns the cue off.
``white_min_share`` is 0.005 since session 35: at 0.001 the few pixels of a rain streak across a red car's back
passed as headlights (6 of the 21 cars flipped on ground-truth masks over held-out trees 2367-2373 with that
session's weights); on its tuning trees 0.005 turned 3 cars the right way and none the wrong way, and on held-out
trees 2375-2381 2 and none (the semantic branch's proposals: 4 and none;
``docs/results/2026-12-02_cpu/session35/lead/flips/``).
Near-white pixels are not only headlights, though: rain streaks cross a red back, and a red body's tail lamps and
light bar are a paler red whose brightest pixels pass as white. On the Table 1 tuning trees 31, 35 and 37 (session
21's demo weights, 407 cars on ground-truth masks, an oracle) they were on 12 front views and on 14 back or side
views of red bodies: a coin, while their absence was right on 24 of 25, and the MultiBin bins named the right end
of 21 of those 26. So a presence counts ``headlight_weight`` (0.3, the bins' weight ``-flip_below``) of the red
lamps' evidence: it seldom turns the branch's yaw by itself (:func:`face_by_reading`: only with its side term), and
in the fit's belief (:func:`~sdn3d.geometric.facing.facing_belief`) it weighs as much as sure bins, so that where
the two disagree the silhouette decides (``docs/results/2026-11-30_cpu/session22/flip``). The absence keeps
``absent_weight``. The bins are then as good as the training: a second demo training's called every red body a
back, and on tree 35 the weight fixed 17 fits of back views (oracle masks and proposals) and broke 4 fits of
true fronts whose headlights were real. A headlight also sits in the body: only near-white pixels between the
leftmost and the rightmost red pixel of the rows within ``headlight_rows`` (a share of the crop's side: 2 rows of a
64-px crop) of their own count (:func:`in_the_body`). What a mask spills onto beside the body (a lane marking, the
road, a neighbour's pale paint: the semantic branch's proposals) does not; a lamp at the body's corner, which ends
its own row, has the bumper or the bonnet beside it and does; a rain streak across the body still does. On the
Table 1 tuning trees 33, 35 and 37 (session 21's demo weights; 31 showed no red body) the near-white pixels were on
24 of 27 front views and 12 of 37 back views of red bodies on ground-truth masks (an oracle), 20 of 23 and 27 of 34
on the semantic branch's proposals; within the body, on 24 of 27 and 8 of 37, 19 of 23 and 7 of 34 (the front lost
read a spill too). Within each pixel's own row only (0) it lost 2 oracle fronts whose headlights end their rows
(``docs/results/2026-11-30_cpu/session25/pose40``).
The semantic branch's proposals spill past their cars, up and sideways onto red-bordered road signs, and the red test
read a sign as tail lamps: a front view turned to a back, and on a back view the sign's rows joined the lamps' and
failed the one-band test, so the net's belief in a front won. A car's roof and glass carry no lamps (they sit at the
belt line or below, about the middle of a back view's height and lower): red pixels in the top ``lamp_top`` (0.3) of
the rows the mask covers are not read. On the tuning trees 35, 37, 39, 41 and 43 (session 34's demo weights), the fit
on the proposals turned 10 more cars the right way and none the wrong way (99 flips of 409 to 89), and no fit on
ground-truth masks changed; on the held-out trees 2351-2357, 6 more and none the wrong way (87 of 341 to 81),
ground-truth masks again unchanged (``docs/results/2026-12-02_cpu/session34/lead/lamptop``); 0 reads every row.

A car cut by the image's left or right border (the predictor's ``border_side``, :func:`border_side`) lies beside the
camera, and there the end facing it (the near end, towards ``sign(sin(alpha)) cos(alpha)`` across the image, the
same for a yaw and its reverse) lies at the border: a car along the road, off to one side, is seen with its near end
outwards. So its near end's lamps, red or white, are cut off, and their absence says nothing about the end. On the
Table 1 tuning trees 31, 35 and 37 (session 21's demo weights, ground-truth masks, an oracle) the truth put the near
end at the cutting border on 66 of the 68 cut cars (the 2 others cut by the bottom only), and with no red lamps the
absence was right on 25 front views and wrong on all 17 back views
(``docs/results/2026-11-30_cpu/session23/border``). What the picture still tells is the car's place: with
``traffic`` :attr:`Traffic.RIGHT` (KITTI's, Virtual KITTI's and Cityscapes' roads) a car cut by the right border
drives, or is parked, the camera's way and shows its back, and one cut by the left border comes towards the camera
and shows its front; on those trees that side named the true end of 46 of the 51 cut cars without lamps. So on a car
the left or right border cuts, an absence of red lamps (or of a red body's headlights) is replaced by that side's
evidence at ``side_weight`` (0.5, as ``absent_weight``), ``-side_weight * side * sin(alpha)`` (``side`` +1 for the
right border, -1 for the left; :attr:`Traffic.LEFT` reverses it, :attr:`Traffic.NONE` counts nothing), at every
hypothesis: one that puts the near end inwards is the silhouette's depth reflection (``alpha -> -alpha``, which an
outline hardly tells apart), not a view whose lamps could show. Read only where the hypothesis put the near end at
the border, the rule turned 6 of those trees' fits from flipped to right; at every hypothesis 14, breaking none (the
fit on ground-truth masks, 35 flips to 21). Lamps that are seen still count as before. Counting the absence for
nothing (:attr:`Traffic.NONE`) leaves the end to the MultiBin bins, right on 5 of those 17 backs: on the seed-13
tree such an abstention made 16 of 61 cut cars face the wrong way against 9, and on trees 31/35/37 it broke 3 more
cars than it fixed (``docs/results/2026-11-30_cpu/session22/flip``). Weights between were tried in session 36 (the
demo weights of that session, tuning trees 35-43, ground-truth masks): the bins were right on 38 of the 87 cut cars
without lamps, the side on 80; at ``side_weight`` 0.3 or less (below ``-flip_below``: the side no longer turns the
branch's yaw) 27 to 43 cars more faced the wrong way for 1 to 3 fewer, 0.35 and 0.4 changed nothing, and 0.6 turned
1 car of 409 the right way; on held-out trees 2383-2389 0.6 turned none either way (306 cars; 3 fits turned about 30
degrees further off), so 0.5 stays (``docs/results/2026-12-02_cpu/session36/flips``).

Fog and rain add the air's light to every pixel (``observed = t albedo + air``): a tail lamp's red over green
falls from about 2.3 to 1.5 in rain, below ``ratio``, and a back view without "red lamps" was read as a front (Table 1's
rain frames turned a third to a half of the turned cars end for end). Both tests therefore read the colours
through the air (:func:`air_offset`, :func:`through_the_air`): a car's darkest pixels in clear air are about
``clear_dark`` (tyres and glass: 0.10 on the clone frames' crops), so darks above it are the air's; the air is
taken off and the rest divided by ``t``. In clear air (darks at most ``clear_dark``) nothing changes; ``None``
reads the colours as they are. Tuning and the choice of 0.10: ``docs/results/2026-11-29_cpu/session9/fogflip``.

:func:`lamp_evidence` scores hypotheses; :func:`face_by_lamps` turns each predicted yaw end for end where the
lamps clearly disagree with it (the geometric predictor's ``lamp_cue``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

import torch
from torch import Tensor

__all__ = ["LampCue", "Traffic", "border_side", "air_offset", "through_the_air", "red_lamps", "white_lamps",
           "in_the_body", "read_lamps", "lamp_evidence", "evidence_of", "face_by_lamps", "face_by_reading"]


class Traffic(StrEnum):
    """The side of the road traffic keeps to: which end a car cut by the image border shows (module doc)."""

    RIGHT = "right"  # KITTI, Virtual KITTI, Cityscapes: cut by the right border, its back; by the left, its front
    LEFT = "left"
    NONE = "none"  # no side: a cut car's absence of lamps counts for nothing

    @classmethod
    def parse(cls, value: object, key: str, error: type[Exception] = ValueError) -> Traffic:
        """``value`` (a user's string, or a :class:`Traffic`) as a :class:`Traffic`.

        Raises:
            error: naming ``key`` and the values, for anything else (any type).
        """
        try:
            return cls(value)
        except ValueError:
            raise error(f"{key} must be one of {', '.join(t.value for t in cls)}, got {value!r}") from None


@dataclass(frozen=True)
class LampCue:
    """Thresholds of the red-lamp cue and of the red bodies' headlights, and the traffic's side (module doc)."""

    red_min: float = 0.25
    ratio: float = 2.0
    min_pixels: int = 3
    max_share: float = 0.12
    max_row_spread: float = 0.12
    min_mask: int = 150
    absent_weight: float = 0.5
    flip_below: float = -0.3
    red_body: bool = True
    white_min: float = 0.55
    white_spread: float = 0.25
    white_min_share: float = 0.005
    headlight_weight: float = 0.3
    headlight_rows: float = 0.03
    clear_dark: float | None = 0.10
    lamp_top: float = 0.3
    traffic: Traffic = Traffic.RIGHT
    side_weight: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "traffic", Traffic.parse(self.traffic, "LampCue.traffic"))
        if isinstance(self.headlight_rows, bool) or not (isinstance(self.headlight_rows, (int, float))
                                                         and 0.0 <= self.headlight_rows <= 1.0):
            raise ValueError(f"LampCue.headlight_rows must lie in [0, 1] (a share of the crop's side), got "
                             f"{self.headlight_rows!r}")
        if not 0.0 <= self.headlight_weight <= 1.0:
            raise ValueError(f"LampCue.headlight_weight must lie in [0, 1] (a share of the red lamps' evidence), "
                             f"got {self.headlight_weight}")
        if isinstance(self.lamp_top, bool) or not (isinstance(self.lamp_top, (int, float))
                                                   and 0.0 <= self.lamp_top < 1.0):
            raise ValueError(f"LampCue.lamp_top must lie in [0, 1) (a share of the mask's rows from its top), got "
                             f"{self.lamp_top!r}")
        if isinstance(self.side_weight, bool) or not (isinstance(self.side_weight, (int, float))
                                                      and 0.0 <= self.side_weight <= 1.0):
            raise ValueError(f"LampCue.side_weight must lie in [0, 1] (the traffic side's weight on a cut car), got "
                             f"{self.side_weight!r}")


def border_side(box: Tensor, width: int) -> Tensor:
    """``(N,)`` float: the image border that cuts each pixel-centre ``(l, t, r, b)`` box of ``box (N, 4)`` in an
    image ``width`` pixels wide: -1 the left one (``l`` in the first column), +1 the right one (``r`` in the last),
    0 neither or both (a box across the whole image has no side).

    >>> border_side(torch.tensor([[0.0, 5, 40, 30], [200, 5, 311, 30], [0, 5, 311, 30], [9, 5, 40, 30]]), 312)
    tensor([-1.,  1.,  0.,  0.])
    """
    if box.dim() != 2 or box.shape[1] != 4:
        raise ValueError(f"box must be (N, 4), got {tuple(box.shape)}")
    left, right = box[:, 0] < 0.5, box[:, 2] > width - 1.5
    return right.to(box.dtype) - left.to(box.dtype)


def air_offset(crop: Tensor, mask: Tensor, clear_dark: float | None) -> tuple[Tensor, Tensor]:
    """``(air (N, 3), t (N,))``: the light haze adds to every pixel of each ``(N, 3, S, S)`` crop's ``(N, S, S)``
    bool mask, and the share ``t`` of the car's own light that reaches the camera (``observed = t albedo + air``,
    module doc). The air is grey (fog and rain are; a car's coloured darks are its paint): the darks (5 % quantile
    per channel, the least of the three) are ``t clear_dark + air`` and ``t = 1 - air / bright``, ``bright`` the
    brightest pixels (95 % quantile, mean of the channels: nearly the air's own light in thick haze), solved for
    ``air`` (at least 0); ``t`` in ``[0.05, 1]``. Clear air (darks at most ``clear_dark``), ``clear_dark`` None or
    an empty mask: zeros and ones."""
    if clear_dark is None or crop.shape[0] == 0:
        return crop.new_zeros(crop.shape[0], 3), crop.new_ones(crop.shape[0])
    masked = torch.where(mask[:, None], crop, torch.full_like(crop, math.nan)).flatten(2)
    q = torch.nanquantile(masked, torch.tensor([0.05, 0.95], dtype=crop.dtype, device=crop.device), dim=2)
    bright = q[1].nan_to_num(1.0).mean(1, keepdim=True).clamp_min(2 * clear_dark)
    # darks = t clear_dark + air and t = 1 - air / bright: solved for the air
    dark = q[0].nan_to_num(clear_dark).amin(1, keepdim=True)
    air = ((dark - clear_dark) / (1 - clear_dark / bright)).clamp_min(0).expand(-1, 3)
    return air, (1 - air.mean(1) / bright[:, 0]).clamp(0.05, 1.0)


def through_the_air(crop: Tensor, mask: Tensor, clear_dark: float | None) -> Tensor:
    """``(N, 3, S, S)``: the colours of ``crop`` as the car shows them in clear air, ``(observed - air) / t``
    (:func:`air_offset` of its ``(N, S, S)`` bool ``mask``)."""
    air, t = air_offset(crop, mask, clear_dark)
    return (crop - air[:, :, None, None]) / t[:, None, None, None]


def _red(seen: Tensor, mask: Tensor, cue: LampCue) -> Tensor:
    """``(N, S, S)`` bool: the saturated red pixels of the ``(N, S, S)`` bool ``mask`` in ``seen (N, 3, S, S)``, the
    crops' colours read through the air (:func:`through_the_air`)."""
    r, g, b = seen[:, 0], seen[:, 1], seen[:, 2]
    return mask & (r > cue.red_min) & (r > cue.ratio * g) & (r > cue.ratio * b)


def red_lamps(crop: Tensor, mask: Tensor, cue: LampCue | None = None) -> tuple[Tensor, Tensor, Tensor]:
    """``(present (N,) bool, usable (N,) bool, offset (N,))`` of ``(N, 3, S, S)`` crops in ``[0, 1]`` and their
    ``(N, 1, S, S)`` (or ``(N, S, S)``) masks: red lamps found, whether the cue can be used (module doc), and the
    red pixels' mean column offset from the mask's, over the mask's width (0 where none). The red pixels of the top
    ``cue.lamp_top`` of the mask's rows are left out (a road sign the mask spilled onto above the car)."""
    cue = cue or LampCue()
    m = (mask[:, 0] if mask.dim() == 4 else mask) > 0.5
    rows = torch.arange(crop.shape[-2], dtype=crop.dtype, device=crop.device)[:, None]
    mask_rows = m.any(2)  # (N, S)
    top = torch.where(mask_rows, rows[:, 0], torch.full_like(rows[:, 0], math.inf)).amin(1)
    bottom = torch.where(mask_rows, rows[:, 0], torch.full_like(rows[:, 0], -math.inf)).amax(1)
    height = (bottom - top + 1).clamp_min(1)
    red = _red(through_the_air(crop, m, cue.clear_dark), m, cue)
    if cue.lamp_top > 0:  # no lamp in the roof's rows: a red sign the mask spilled onto above the car
        red = red & (rows[None] >= (top + cue.lamp_top * height)[:, None, None])
    n_red, n_mask = red.flatten(1).sum(1), m.flatten(1).sum(1)
    offset = _column_offset(m, red, crop.dtype)
    red_row = (red * rows).flatten(1).sum(1) / n_red.clamp_min(1)
    spread = ((red * (rows - red_row[:, None, None]) ** 2).flatten(1).sum(1) / n_red.clamp_min(1)).sqrt()
    big = n_mask >= cue.min_mask
    present = n_red >= cue.min_pixels
    usable = big & (n_red <= cue.max_share * n_mask) & (spread <= cue.max_row_spread * height)
    return present, usable, offset


def _column_offset(mask: Tensor, lamps: Tensor, dtype: torch.dtype) -> Tensor:
    """``(N,)``: the mean column of the ``lamps (N, S, S)`` pixels from the ``mask (N, S, S)``'s mean column, over the
    mask's width (0 where no lamp pixel): which side of the vehicle its lamps are on."""
    cols = torch.arange(mask.shape[-1], dtype=dtype, device=mask.device)
    mask_cols = mask.any(1)  # (N, S)
    left = torch.where(mask_cols, cols, torch.full_like(cols, math.inf)).amin(1)
    right = torch.where(mask_cols, cols, torch.full_like(cols, -math.inf)).amax(1)
    width = (right - left + 1).clamp_min(1)
    n_mask, n_lamps = mask.flatten(1).sum(1), lamps.flatten(1).sum(1)
    mean_col = (mask * cols).flatten(1).sum(1) / n_mask.clamp_min(1)
    lamp_col = (lamps * cols).flatten(1).sum(1) / n_lamps.clamp_min(1)
    return torch.where(n_lamps > 0, (lamp_col - mean_col) / width, torch.zeros_like(width))


def white_lamps(crop: Tensor, mask: Tensor, cue: LampCue | None = None) -> tuple[Tensor, Tensor, Tensor]:
    """``(present (N,) bool, usable (N,) bool, offset (N,))`` of the headlights of red-bodied vehicles (module doc):
    usable where the crop is large enough and its red share is over ``cue.max_share`` (the red cue cannot read it;
    never with ``cue.red_body`` false); present where the near-white pixels of the mask's lower half within the red
    body (:func:`in_the_body`, the rows within ``cue.headlight_rows`` of the crop's side) are at least
    ``cue.white_min_share`` of the mask; offset: their mean column's from the mask's, over the mask's width.

    >>> crop, mask = torch.zeros(1, 3, 8, 8), torch.ones(1, 1, 8, 8)
    >>> crop[:, 0] = 0.7  # a red body ...
    >>> crop[0, :, 6, 6] = 0.9  # ... with a white lamp low on its right
    >>> [v.tolist() for v in white_lamps(crop, mask, LampCue(min_mask=0))]
    [[True], [True], [0.3125]]
    """
    cue = cue or LampCue()
    m = (mask[:, 0] if mask.dim() == 4 else mask) > 0.5
    seen = through_the_air(crop, m, cue.clear_dark)  # read once: the red test and the white one
    red = _red(seen, m, cue)
    n_red, n_mask = red.flatten(1).sum(1), m.flatten(1).sum(1)
    rows = torch.arange(crop.shape[-2], device=crop.device)[:, None].expand(crop.shape[-2:])
    top = torch.where(m, rows, torch.full_like(rows, crop.shape[-2])).flatten(1).amin(1)
    bottom = torch.where(m, rows, torch.full_like(rows, -1)).flatten(1).amax(1)
    lower = rows[None] * 2 > (top + bottom)[:, None, None]  # below the mask's middle row
    high, low = seen.amax(1), seen.amin(1)
    body = in_the_body(red, round(cue.headlight_rows * crop.shape[-2]))
    white = m & lower & (low > cue.white_min) & (high - low < cue.white_spread) & body
    n_white = white.flatten(1).sum(1)
    offset = _column_offset(m, white, crop.dtype)
    usable = (n_mask >= cue.min_mask) & (n_red > cue.max_share * n_mask) & cue.red_body
    present = (n_white > 0) & (n_white >= cue.white_min_share * n_mask)
    return present, usable, offset


def in_the_body(red: Tensor, rows: int) -> Tensor:
    """``(N, S, S)`` bool: the pixels between the leftmost and the rightmost pixel of ``red (N, S, S)`` (a red body) of
    the rows within ``rows`` of theirs: where a red body's headlights can be (module doc). A lamp at the body's
    corner has the bumper or the bonnet beside it a row or two away; a lane marking or the road beside the body,
    which a mask spills onto, has no red beyond it.

    >>> red = torch.zeros(1, 3, 6, dtype=torch.bool)
    >>> red[0, 0, [1, 4]] = True  # the bonnet, row 0
    >>> red[0, 2, 2] = True  # row 2: one red pixel
    >>> in_the_body(red, 0)[0].int().tolist()
    [[0, 1, 1, 1, 1, 0], [0, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0]]
    >>> in_the_body(red, 1)[0].int().tolist()  # row 1 (no red of its own) takes the span of rows 0 and 2
    [[0, 1, 1, 1, 1, 0], [0, 1, 1, 1, 1, 0], [0, 0, 1, 0, 0, 0]]
    """
    width = red.shape[-1]
    cols = torch.arange(width, dtype=torch.float32, device=red.device)
    left = torch.where(red, cols, torch.full_like(cols, width)).amin(2)  # (N, S): each row's leftmost red column
    right = torch.where(red, cols, torch.full_like(cols, -1)).amax(2)
    if rows > 0:  # the extremes over the rows within `rows`
        left = -torch.nn.functional.max_pool1d(-left[:, None], 2 * rows + 1, stride=1, padding=rows)[:, 0]
        right = torch.nn.functional.max_pool1d(right[:, None], 2 * rows + 1, stride=1, padding=rows)[:, 0]
    return (cols >= left[:, :, None]) & (cols <= right[:, :, None])


def read_lamps(crop: Tensor, lamp_mask: Tensor, cue: LampCue, given: Tensor | None = None,
               tail_mask: Tensor | None = None) -> tuple[tuple[Tensor, Tensor, Tensor], tuple[Tensor, Tensor, Tensor]]:
    """``(red, white)``: the lamp cue's reading of ``(N, 3, S, S)`` crops, each ``(present, usable, offset)`` of
    ``(N,)`` (:func:`red_lamps` and :func:`white_lamps`) over the ``(N, 1, S, S)`` pixels ``lamp_mask``. With
    ``tail_mask`` (``(N, 1, S, S)``), where ``lamp_mask`` shows no usable red lamps, the red test reads those pixels
    of ``given`` (the crops unmasked) instead; the headlights' test keeps ``lamp_mask``
    (:meth:`~sdn3d.geometric.predict.GeometricPredictor.predict`'s ``tail_mask``)."""
    seen = crop * lamp_mask
    red = red_lamps(seen, lamp_mask, cue)
    if tail_mask is not None:  # only where the mask itself shows no usable red lamps
        past = red_lamps((crop if given is None else given) * tail_mask, tail_mask, cue)
        shown = red[0] & red[1]
        red = tuple(torch.where(shown, a, b) for a, b in zip(red, past, strict=True))
    return red, white_lamps(seen, lamp_mask, cue)


def lamp_evidence(crop: Tensor, mask: Tensor, alpha: Tensor, cue: LampCue | None = None) -> Tensor:
    """``(N, K)`` evidence of the lamps for local orientations ``alpha (N, K)`` (module doc; 0: no cue): the red
    tail lights', and on red bodies the white headlights'."""
    cue = cue or LampCue()
    return evidence_of(*red_lamps(crop, mask, cue), alpha, cue, front=white_lamps(crop, mask, cue))


def evidence_of(present: Tensor, usable: Tensor, offset: Tensor, alpha: Tensor, cue: LampCue | None = None,
                front: tuple[Tensor, Tensor, Tensor] | None = None, border: Tensor | None = None) -> Tensor:
    """``(N, K)`` evidence for local orientations ``alpha (N, K)`` of a :func:`red_lamps` reading ``(present,
    usable, offset)`` (each ``(N,)``; module doc) and, where given, a :func:`white_lamps` reading ``front`` (usable
    only where the red one is not). ``border (N,)``: the image border that cuts each object (:func:`border_side`;
    None: none does); on a cut object an absence of lamps gives way to the traffic's side (module doc). A seen lamp
    counts whatever the border."""
    cue = cue or LampCue()
    sin, cos = torch.sin(alpha), torch.cos(alpha)
    seen = -(sin + 2 * offset[:, None] * cos)
    absent = cue.absent_weight * sin
    if border is not None:
        absent = _cut_absence(absent, sin, border, cue)
    evidence = torch.where(present[:, None], seen, absent)
    evidence = torch.where(usable[:, None], evidence, torch.zeros_like(evidence))
    if front is None:
        return evidence
    f_present, f_usable, f_offset = front
    no_headlights = -cue.absent_weight * sin
    if border is not None:
        no_headlights = _cut_absence(no_headlights, sin, border, cue)
    # near-white pixels are as often rain or a paler tail lamp as headlights: a presence weighs headlight_weight
    headlights = torch.where(f_present[:, None], cue.headlight_weight * (sin + 2 * f_offset[:, None] * cos),
                             no_headlights)
    return torch.where(f_usable[:, None] & ~usable[:, None], headlights, evidence)


def _cut_absence(absent: Tensor, sin: Tensor, border: Tensor, cue: LampCue) -> Tensor:
    """``(N, K)``: an absence's evidence ``absent`` at hypotheses of ``sin(alpha) (N, K)``, replaced by the traffic
    side's on the objects that the ``border (N,)`` cuts (-1 left, +1 right, 0 none; module doc)."""
    side = border[:, None].to(sin.dtype)
    sign = {Traffic.RIGHT: 1.0, Traffic.LEFT: -1.0, Traffic.NONE: 0.0}[cue.traffic]
    # the near end, and its lamps, lie beyond the border: the absence is not read, the car's side of the road is
    return torch.where(side != 0, -sign * cue.side_weight * side * sin, absent)


def face_by_lamps(ry: Tensor, ray: Tensor, crop: Tensor, mask: Tensor, cue: LampCue | None = None,
                  border: Tensor | None = None) -> Tensor:
    """``(N,)`` yaws: each ``ry`` turned end for end where the lamps' evidence for it is below ``cue.flip_below``
    and its reverse is believed more (``ray (N,)``: the angle of the ray through each box, ``alpha = ry - ray``;
    ``border (N,)``: :func:`border_side` of each box, None: none cut)."""
    cue = cue or LampCue()
    return face_by_reading(ry, ray, red_lamps(crop, mask, cue), white_lamps(crop, mask, cue), cue, border)


def face_by_reading(ry: Tensor, ray: Tensor, red: tuple[Tensor, Tensor, Tensor],
                    white: tuple[Tensor, Tensor, Tensor] | None, cue: LampCue | None = None,
                    border: Tensor | None = None) -> Tensor:
    """:func:`face_by_lamps` from the readings themselves: ``red`` of :func:`red_lamps` and ``white`` of
    :func:`white_lamps` (None: no headlight reading), each ``(present, usable, offset)`` of ``(N,)``; e.g. the red
    test read over more pixels than the headlights' (:meth:`~sdn3d.geometric.predict.GeometricPredictor.predict`'s
    ``tail_mask``); ``border (N,)``: :func:`border_side` of each box (None: none cut).

    >>> back = (torch.tensor([True]), torch.tensor([True]), torch.zeros(1))  # red lamps, centred
    >>> round(face_by_reading(torch.tensor([math.pi / 2]), torch.zeros(1), back, None).item(), 4)  # front: turned
    -1.5708
    """
    cue = cue or LampCue()
    alpha = torch.stack([ry - ray, ry - ray + math.pi], 1)
    evidence = evidence_of(*red, alpha, cue, front=white, border=border)
    flip = (evidence[:, 0] < cue.flip_below) & (evidence[:, 1] > evidence[:, 0])
    turned = torch.where(flip, ry + math.pi, ry)
    return torch.atan2(torch.sin(turned), torch.cos(turned))
