"""A learnt correction of the rays' fill (the photo appearance's ``fill='learnt'``; step 2 of
:mod:`sdn3d.editing.photo`).

:func:`~sdn3d.editing.photo.road.ray_fill` carries the road's lines and grain through a vacated region, but its
colours are those of the pixels at the hole's edge: where a large removal reaches the vanishing point the truth is far
road fading into fog, facades or trees, which no ray's ends show. :class:`FillNet` is a small U-Net trained on the
synthetic generator's exact delete pairs (``sdn3d-synth counterfactual_cars=N``: the frame rendered with and without
each car) to predict, from the rays-filled picture around each connected part of the hole, a smooth correction
added inside that part only:

- **crop** (:func:`crop_boxes`): the part's bounding box grown by :data:`CROP_GROW` of its larger side on every side
  (the context the colours come from), made square and kept inside the picture, resampled to the net's working
  side (``FillNet.side``, saved with its weights; :data:`WORK_SIDE` by default);
- **inputs** (:data:`IN_CHANNELS`, :func:`net_inputs`): the rays-filled crop (RGB), the hole and the other objects'
  pixels (``keep_out``) of the crop, and each crop pixel's place in the picture (row and column over the picture's
  height and width, in [-1, 1]: how near the horizon it lies);
- **output**: an RGB correction at :data:`WORK_SIDE`, upsampled (bilinear) to the crop and added to the rays' fill
  in the hole, faded in from the hole's edge (:func:`feather`): the rays' grain and markings stay, their colour and
  brightness move (the last layer starts at zero, so an untrained net is the rays' fill).

A weights file holds one net or several (:class:`FillEnsemble`: nets trained alike from different seeds, whose
corrections are averaged; one net's correction moves by about 0.2 dB with its training seed). Weights are saved by
:func:`save_fill_net` and read by :func:`load_fill_net` (``torch.load(weights_only=True)``: a dict of tensors and
plain values, checked by name); :func:`train_fill_net` trains on :class:`FillSamples`
deterministically given its seed (1 thread). The training data comes from ``benchmarks/learnt_fill.py``, which
draws each delete pair of counterfactual trees with ``fill='rays'`` and keeps what :func:`crop_samples` takes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch
import torch.nn.functional as F
from torch import Tensor, nn

from sdn3d.editing.photo.settings import PhotoSettingsError

__all__ = ["FillNet", "FillEnsemble", "FillSamples", "TrainSettings", "WORK_SIDE", "CROP_GROW", "FEATHER_SHARE",
           "MIN_PART_PX", "IN_CHANNELS", "WEIGHTS_FORMAT", "DEFAULT_WEIGHTS", "crop_boxes", "feather", "net_inputs",
           "learnt_fill", "crop_samples", "train_fill_net", "save_fill_net", "load_fill_net", "read_fill_meta",
           "default_weights_path"]

#: Default side (pixels) of the square crop the net sees (``FillNet.side``): a hole part's box grown by
#: :data:`CROP_GROW`, resampled.
WORK_SIDE = 32
#: A hole part's crop is its bounding box grown by this share of its larger side on every side (the context).
CROP_GROW = 0.5
#: The correction fades in from the hole's edge over this share of the part's box side (at least 2 px): the rays' fill
#: is right at the edge, where it starts from the known pixels, and a correction there draws the crop's box as a seam.
FEATHER_SHARE = 0.15
#: Hole parts of fewer pixels keep the rays' fill (a sliver: no colour to correct at the working scale).
MIN_PART_PX = 16
#: The net's input channels: rays-filled RGB, hole, keep_out, row and column in the picture.
IN_CHANNELS = 7
#: ``format`` of a weights file (:func:`save_fill_net`).
WEIGHTS_FORMAT = "sdn3d-learnt-fill-v2"
#: The packaged weights' file name in :mod:`sdn3d.resources` (``photo.learnt_weights`` null).
DEFAULT_WEIGHTS = "learnt_fill.pt"


def default_weights_path() -> Path:
    """The packaged weights (:data:`DEFAULT_WEIGHTS` in :mod:`sdn3d.resources`)."""
    import sdn3d.resources

    return Path(sdn3d.resources.__file__).with_name(DEFAULT_WEIGHTS)


class FillNet(nn.Module):
    """A three-level U-Net (``width``, 2 ``width``, 4 ``width`` channels) with a global-average context vector at
    its bottom: ``(B, IN_CHANNELS, S, S) -> (B, 3, S, S)`` correction, ``S`` its working ``side`` (the crops'
    side, divisible by 4; the net's weights do not depend on it, its training does)."""

    def __init__(self, width: int = 16, side: int = WORK_SIDE) -> None:
        super().__init__()
        if side < 8 or side % 4:
            raise ValueError(f"FillNet: side must be a multiple of 4 from 8, got {side}")
        w = width
        self.width = width
        self.side = side

        def block(cin: int, cout: int) -> nn.Sequential:
            return nn.Sequential(nn.Conv2d(cin, cout, 3, padding=1), nn.LeakyReLU(0.1),
                                 nn.Conv2d(cout, cout, 3, padding=1), nn.LeakyReLU(0.1))

        self.enc1 = block(IN_CHANNELS, w)
        self.enc2 = block(w, 2 * w)
        self.enc3 = block(2 * w, 4 * w)
        self.context = nn.Linear(4 * w, 4 * w)
        self.dec2 = block(4 * w + 2 * w, 2 * w)
        self.dec1 = block(2 * w + w, w)
        self.out = nn.Conv2d(w, 3, 3, padding=1)
        nn.init.zeros_(self.out.weight)  # an untrained net leaves the rays' fill as it is
        nn.init.zeros_(self.out.bias)

    def forward(self, x: Tensor) -> Tensor:
        e1 = self.enc1(x)
        e2 = self.enc2(F.avg_pool2d(e1, 2))
        e3 = self.enc3(F.avg_pool2d(e2, 2))
        # The whole crop's summary (fog level, how much of it is road) reaches every pixel.
        e3 = e3 + F.leaky_relu(self.context(e3.mean((2, 3))), 0.1)[:, :, None, None]
        d2 = self.dec2(torch.cat([F.interpolate(e3, scale_factor=2.0, mode="bilinear", align_corners=False), e2], 1))
        d1 = self.dec1(torch.cat([F.interpolate(d2, scale_factor=2.0, mode="bilinear", align_corners=False), e1], 1))
        return self.out(d1)


class FillEnsemble(nn.Module):
    """Several :class:`FillNet` of one working ``side``: ``(B, IN_CHANNELS, S, S) -> (B, 3, S, S)``, the mean of
    their corrections."""

    def __init__(self, nets: list[FillNet]) -> None:
        super().__init__()
        if not nets or len({net.side for net in nets}) != 1:
            raise ValueError(f"FillEnsemble: one net or more, of one working side, got sides {[n.side for n in nets]}")
        self.nets = nn.ModuleList(nets)
        self.side = nets[0].side

    def forward(self, x: Tensor) -> Tensor:
        return torch.stack([net(x) for net in self.nets]).mean(0)


def crop_boxes(hole: Tensor, grow: float = CROP_GROW, min_pixels: int = MIN_PART_PX) -> tuple[list, Tensor]:
    """``(boxes, labels (H, W) int64)``: one square box ``(y0, y1, x0, x1)`` per connected part (8-connected) of
    ``hole (H, W)`` with at least ``min_pixels`` pixels (its bounding box grown by ``grow`` of its larger side on
    every side, squared, shifted inside the picture; at most the picture's smaller side), and each pixel's part
    (0: none; parts are numbered as the boxes, from 1)."""
    import cv2

    height, width = hole.shape
    count, labels, stats, _ = cv2.connectedComponentsWithStats(hole.numpy().astype(np.uint8), connectivity=8)
    boxes = []
    keep = np.zeros(count, np.int64)
    for k in range(1, count):
        x, y, w, h, n = (int(v) for v in stats[k])
        if n < min_pixels:
            continue
        side = min(round(max(w, h) * (1 + 2 * grow)) + 8, height, width)
        cy, cx = y + h / 2, x + w / 2
        y0 = int(min(max(round(cy - side / 2), 0), height - side))
        x0 = int(min(max(round(cx - side / 2), 0), width - side))
        boxes.append((y0, y0 + side, x0, x0 + side))
        keep[k] = len(boxes)
    return boxes, torch.from_numpy(keep[labels])


def net_inputs(filled: Tensor, hole: Tensor, keep_out: Tensor | None, boxes: list,
               side: int = WORK_SIDE) -> Tensor:
    """``(B, IN_CHANNELS, side, side)`` float32 inputs of :class:`FillNet` for ``boxes`` (:func:`crop_boxes`) of the
    rays-filled ``filled (3, H, W)`` with ``hole (H, W)`` and ``keep_out (H, W)`` (None: no other objects): each
    box resampled by area (module doc)."""
    height, width = hole.shape
    others = torch.zeros_like(hole) if keep_out is None else keep_out & ~hole
    planes = torch.cat([filled.float().clamp(0, 1), hole[None].float(), others[None].float()])  # (5, H, W)
    rows = torch.linspace(-1, 1, height)
    cols = torch.linspace(-1, 1, width)
    out = []
    for y0, y1, x0, x1 in boxes:
        crop = F.interpolate(planes[None, :, y0:y1, x0:x1], size=(side, side), mode="area")[0]
        # Each working pixel's place: the mean row and column of the picture pixels it covers.
        r = F.interpolate(rows[None, None, y0:y1, None], size=(side, 1), mode="area")[0, 0, :, 0]
        c = F.interpolate(cols[None, None, None, x0:x1], size=(1, side), mode="area")[0, 0, 0]
        out.append(torch.cat([crop, r[None, :, None].expand(1, side, side), c[None, None, :].expand(1, side, side)]))
    return torch.stack(out) if out else torch.zeros(0, IN_CHANNELS, side, side)


def feather(part: Tensor, share: float = FEATHER_SHARE) -> Tensor:
    """``(h, w)`` float in [0, 1]: each pixel of ``part (h, w)`` bool's distance to its edge over ``share`` of the
    part's box's larger side (at least 2 px), capped at 1; 0 outside ``part``."""
    import cv2

    ys, xs = part.nonzero(as_tuple=True)
    if not len(ys):
        return torch.zeros(part.shape)
    side = max(int(ys.max() - ys.min()), int(xs.max() - xs.min())) + 1
    padded = np.pad(part.numpy().astype(np.uint8), 1)
    depth = torch.from_numpy(cv2.distanceTransform(padded, cv2.DIST_L2, 3)[1:-1, 1:-1])
    return (depth / max(share * side, 2.0)).clamp(0, 1) * part


@torch.no_grad()
def learnt_fill(filled: Tensor, hole: Tensor, net: FillNet | FillEnsemble, keep_out: Tensor | None = None) -> Tensor:
    """``filled (3, H, W)`` (the rays' fill of ``hole (H, W)``) with ``net``'s correction added inside each
    part of ``hole`` (:func:`crop_boxes`; pixels outside ``hole`` and parts under :data:`MIN_PART_PX` unchanged),
    clamped to [0, 1]."""
    boxes, labels = crop_boxes(hole)
    if not boxes:
        return filled.clone()
    net.eval()
    correction = net(net_inputs(filled, hole, keep_out, boxes, net.side))  # (B, 3, S, S); no graph: @no_grad
    out = filled.clone()
    for k, (y0, y1, x0, x1) in enumerate(boxes):
        up = F.interpolate(correction[k : k + 1], size=(y1 - y0, x1 - x0), mode="bilinear", align_corners=False)[0]
        part = labels[y0:y1, x0:x1] == k + 1
        window = out[:, y0:y1, x0:x1]
        ramp = feather(part).to(window.dtype)
        out[:, y0:y1, x0:x1] = torch.where(part[None], (window + ramp * up.to(window.dtype)).clamp(0, 1), window)
    return out


# -- training ---------------------------------------------------------------------------------------------------------


@dataclass
class FillSamples:
    """Training crops (:func:`crop_samples`): ``inputs (N, IN_CHANNELS, S, S)`` as :func:`net_inputs`; ``filled`` and
    ``target (N, 3, L, L)`` the rays' fill and the exact render at the loss's side ``L`` (a multiple of ``S``);
    ``hole (N, L, L)`` bool the part scored; ``ramp (N, L, L)`` its :func:`feather` (drawn at the picture's size);
    ``group (N,)`` int64 the pair each crop came from."""

    inputs: Tensor
    filled: Tensor
    target: Tensor
    hole: Tensor
    ramp: Tensor
    group: Tensor

    @classmethod
    def cat(cls, parts: list[FillSamples]) -> FillSamples:
        return cls(*(torch.cat([getattr(p, f) for p in parts]) for f in ("inputs", "filled", "target", "hole",
                                                                          "ramp", "group")))


def crop_samples(filled: Tensor, hole: Tensor, keep_out: Tensor | None, target: Tensor, group: int,
                 side: int = WORK_SIDE) -> FillSamples:
    """:class:`FillSamples` of one drawn delete: ``filled (3, H, W)`` the rays' fill of ``hole (H, W)`` with
    ``keep_out``, ``target (3, H, W)`` the exact render without the car; one crop per part (:func:`crop_boxes`),
    the net's inputs at ``side``, the loss's planes at twice that."""
    loss_side = 2 * side
    boxes, labels = crop_boxes(hole)
    inputs = net_inputs(filled, hole, keep_out, boxes, side)
    big = []
    for k, (y0, y1, x0, x1) in enumerate(boxes):
        part = labels[y0:y1, x0:x1] == k + 1
        planes = torch.cat([filled[:, y0:y1, x0:x1].float(), target[:, y0:y1, x0:x1].float(), part[None].float(),
                            feather(part)[None].float()])
        big.append(F.interpolate(planes[None], size=(loss_side, loss_side), mode="area")[0])
    big = torch.stack(big) if big else torch.zeros(0, 8, loss_side, loss_side)
    return FillSamples(inputs, big[:, :3], big[:, 3:6], big[:, 6] > 0.5, big[:, 7], torch.full((len(boxes),), group))


@dataclass(frozen=True)
class TrainSettings:
    """:func:`train_fill_net`'s settings: ``width`` of :class:`FillNet`, ``steps`` of Adam at ``lr`` (cosine decay to
    zero) on batches of ``batch`` crops (mirrored left-right at random), ``seed``."""

    width: int = 16
    steps: int = 3000
    batch: int = 32
    lr: float = 2e-3
    seed: int = 0


def _mirror(inputs: Tensor, filled: Tensor, target: Tensor, hole: Tensor, ramp: Tensor, flip: Tensor):
    """The crops of ``flip (B,)`` mirrored left-right (the column plane changes sign)."""
    f, g = flip[:, None, None, None], flip[:, None, None]
    inputs = torch.where(f, inputs.flip(3), inputs)
    inputs[:, 6] = torch.where(g, -inputs[:, 6], inputs[:, 6])
    return inputs, torch.where(f, filled.flip(3), filled), torch.where(f, target.flip(3), target), \
        torch.where(g, hole.flip(2), hole), torch.where(g, ramp.flip(2), ramp)


#: :func:`train_fill_net`'s loss is the mean over crops of ``log(MSE + LOG_FLOOR)``: PSNR, the benchmark's score, is
#: a log of each pair's error, so a pair the rays already fill well counts as much as a poor one (plain MSE let the
#: poor ones rule and the net spoil the good ones); the floor stands for the grain no smooth correction removes.
LOG_FLOOR = 1e-4


def _loss(net: FillNet, inputs: Tensor, filled: Tensor, target: Tensor, hole: Tensor, ramp: Tensor) -> Tensor:
    """The mean over crops of ``log(MSE + LOG_FLOOR)`` inside each crop's hole of the corrected fill (the correction
    upsampled and faded in as :func:`learnt_fill` does) against the target."""
    up = F.interpolate(net(inputs), size=filled.shape[-2:], mode="bilinear", align_corners=False)
    err = ((filled + ramp[:, None] * up).clamp(0, 1) - target).square().sum(1) * hole
    mse = err.sum((1, 2)) / (3 * hole.sum((1, 2)).clamp(min=1))
    return (mse + LOG_FLOOR).log().mean()


def train_fill_net(samples: FillSamples, settings: TrainSettings = TrainSettings(),
                   log: callable | None = None) -> FillNet:
    """A :class:`FillNet` trained on ``samples`` (module doc; deterministic given ``settings.seed`` on one thread);
    ``log(step, loss)`` every 100 steps."""
    gen = torch.Generator().manual_seed(settings.seed)
    torch.manual_seed(settings.seed)
    net = FillNet(settings.width, samples.inputs.shape[-1])
    opt = torch.optim.Adam(net.parameters(), lr=settings.lr)
    n = len(samples.inputs)
    if n == 0:
        raise ValueError("train_fill_net: no training crops")
    running = 0.0
    for step in range(settings.steps):
        for group in opt.param_groups:
            group["lr"] = settings.lr * 0.5 * (1 + math.cos(math.pi * step / settings.steps))
        idx = torch.randint(n, (min(settings.batch, n),), generator=gen)
        flip = torch.rand(len(idx), generator=gen) < 0.5
        batch = _mirror(samples.inputs[idx].clone(), samples.filled[idx], samples.target[idx], samples.hole[idx],
                        samples.ramp[idx], flip)
        loss = _loss(net, *batch)
        opt.zero_grad()
        loss.backward()
        opt.step()
        running += float(loss.detach())
        if log is not None and (step + 1) % 100 == 0:
            log(step + 1, running / 100)
            running = 0.0
    return net.eval()


# -- weights ----------------------------------------------------------------------------------------------------------


def save_fill_net(net: FillNet | FillEnsemble, path: str | Path, meta: dict | None = None) -> None:
    """Write ``net`` (one net or several) to ``path`` atomically, with the user's umask (:func:`sdn3d.io.atomic_write`;
    an earlier file there stays whole until the new one is complete): :data:`WEIGHTS_FORMAT`, the working side, each
    net's width and state dict in float16 (half the file), and ``meta``, plain values only."""
    import io

    from sdn3d.io import atomic_write

    nets = list(net.nets) if isinstance(net, FillEnsemble) else [net]
    members = [{"width": n.width, "state_dict": {k: v.half() for k, v in n.state_dict().items()}} for n in nets]
    buffer = io.BytesIO()
    torch.save({"format": WEIGHTS_FORMAT, "side": net.side, "members": members, "meta": dict(meta or {})}, buffer)
    atomic_write(path, lambda handle: handle.write(buffer.getbuffer()))


def read_fill_meta(path: str | Path) -> dict:
    """The ``meta`` saved with the weights at ``path`` (:func:`save_fill_net`; errors as :func:`load_fill_net`)."""
    return _read_blob(Path(path))["meta"]


def _read_blob(path: Path) -> dict:
    if not path.is_file():
        raise PhotoSettingsError(f"photo.fill=learnt: no weights file {str(path)!r} (photo.learnt_weights; train one "
                                 "with benchmarks/learnt_fill.py train)")
    try:
        blob = torch.load(str(path), map_location="cpu", weights_only=True)
    except Exception as exc:  # noqa: BLE001 - any unreadable file is the same user error
        raise PhotoSettingsError(f"photo.fill=learnt: {str(path)!r} is not a weights file torch can read "
                                 f"({type(exc).__name__})") from exc
    if not isinstance(blob, dict) or blob.get("format") != WEIGHTS_FORMAT:
        raise PhotoSettingsError(f"photo.fill=learnt: {str(path)!r} holds no {WEIGHTS_FORMAT} weights")
    return blob


_CACHE: dict[tuple, FillEnsemble] = {}


def load_fill_net(path: str | Path | None = None) -> FillEnsemble:
    """The nets saved at ``path`` (None: :func:`default_weights_path`) as a :class:`FillEnsemble` (of one net, where
    one was saved), read once per file and change.

    Raises:
        PhotoSettingsError: naming the file, when it is missing, not a torch file, or not :data:`WEIGHTS_FORMAT`
            weights of this net.
    """
    path = Path(path) if path is not None else default_weights_path()
    key = (str(path.resolve()), path.stat().st_mtime_ns, path.stat().st_size) if path.is_file() else None
    if key in _CACHE:
        return _CACHE[key]
    blob = _read_blob(path)
    try:
        nets = []
        for member in blob["members"]:
            net = FillNet(int(member["width"]), int(blob["side"]))
            net.load_state_dict({k: v.float() for k, v in member["state_dict"].items()})
            nets.append(net)
        ensemble = FillEnsemble(nets)
    except (KeyError, TypeError, ValueError, RuntimeError) as exc:
        raise PhotoSettingsError(f"photo.fill=learnt: {str(path)!r}: weights do not fit the net ({exc})") from exc
    _CACHE[key] = ensemble.eval()
    return _CACHE[key]
