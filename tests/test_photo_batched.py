"""The photo appearance's per-frame (batched) steps equal the per-object loops they replaced, bit for bit, on random
inputs: the shadow bands below vacated objects (one max-pool per object), the grown pixels of objects that stay (one
upsample per object), the contact shadows (one whole-canvas blur per object) and the recolouring (one image copy
per object)."""

from __future__ import annotations

import numpy as np
import pytest
import torch
import torch.nn.functional as F

from sdn3d.editing.frame import PixelFrame, upsample_ids
from sdn3d.editing.photo import fill, transfer
from sdn3d.editing.photo.recolor import recolor_pixels
from sdn3d.editing.photo.settings import INPUT, RECOLORED
from sdn3d.image_ops import dilate_square


def _bands_loop(ids, gone, share):
    hole = torch.zeros_like(ids, dtype=torch.bool)
    for k in gone.tolist():
        one = ids == k
        rows = one.any(1).nonzero().flatten()
        if not len(rows):
            continue
        band = max(1, round(share * float(rows.max() - rows.min() + 1)))
        below = F.max_pool2d(F.pad(one[None, None].float(), (0, 0, band, 0)), (band + 1, 1), stride=1)[0, 0] > 0
        hole |= dilate_square(below, 1)
    return hole


def _blobs(gen, height, width, n):
    ids = torch.zeros(height, width, dtype=torch.long)
    for k in range(1, n + 1):
        y, x = int(torch.randint(0, height, (1,), generator=gen)), int(torch.randint(0, width, (1,), generator=gen))
        h, w = int(torch.randint(1, height // 2, (1,), generator=gen)), int(torch.randint(1, width // 3, (1,),
                                                                                        generator=gen))
        ids[y:y + h, x:x + w] = k
    return ids


@pytest.mark.parametrize("seed", range(6))
def test_shadow_bands_equal_one_max_pool_per_object(seed):
    gen = torch.Generator().manual_seed(seed)
    ids = _blobs(gen, 57, 83, 6)
    gone = torch.tensor([2, 4, 5, 9])  # 9: no pixels
    for share in (0.05, 0.3, 1.5):
        assert torch.equal(dilate_square(fill._shadow_bands(ids, gone, share), 1), _bands_loop(ids, gone, share))


class _Table:
    def __init__(self, ids, mask):
        self.instance_id, self.mask = ids, mask


@pytest.mark.parametrize("seed", range(4))
def test_grown_pixels_equal_one_upsample_per_object(seed):
    gen = torch.Generator().manual_seed(seed)
    frame = PixelFrame((125, 41), (60, 20))
    before = _Table(torch.tensor([3, 5, 7, 8]), torch.rand(4, 20, 60, generator=gen) > 0.6)
    after = _Table(torch.tensor([3, 5, 7, 8]), torch.rand(4, 20, 60, generator=gen) > 0.5)
    after.mask[2] = before.mask[2]  # nothing gained
    origin = torch.tensor([0, 1, 2, 3])
    stays = torch.tensor([True, True, True, False])
    own0 = torch.where(torch.rand(41, 125, generator=gen) > 0.7, 5, 0)
    own, grown = own0.clone(), []
    for a in stays.nonzero().flatten().tolist():
        gained = after.mask[a] & ~before.mask[int(origin[a])]
        if bool(gained.any()):
            up = upsample_ids(gained.long(), frame).bool() & (own == 0)
            own = torch.where(up, after.instance_id[a], own)
            grown.append(a)
    got, got_rows = transfer._grow(own0.clone(), before, after, origin, stays, frame)
    assert got_rows == grown and torch.equal(got, own)


def _contact_loop(polys, size):
    import cv2

    canvas = np.zeros(size, np.float32)
    for poly in polys:
        hull = cv2.convexHull(np.round(poly * 4).astype(np.int32))
        layer = np.zeros_like(canvas)
        cv2.fillConvexPoly(layer, hull, 1.0, lineType=cv2.LINE_AA, shift=2)
        span = max(float(poly[:, 1].max() - poly[:, 1].min()), 2.0)
        canvas = np.maximum(canvas, cv2.GaussianBlur(layer, (0, 0), max(0.6, 0.25 * span)))
    return canvas


@pytest.mark.parametrize("seed", range(8))
def test_contact_shadows_equal_one_whole_canvas_blur_per_object(seed, monkeypatch):
    rng = np.random.default_rng(seed)
    size = (375, 1242) if seed < 4 else (61, 97)
    polys = []
    for _ in range(5):
        centre = rng.uniform([-60, -40], [size[1] + 60, size[0] + 40])
        polys.append(centre + rng.uniform(-1, 1, (4, 2)) * rng.uniform(2, 120, 2))
    calls = iter(polys)
    monkeypatch.setattr(transfer, "_box_floor", lambda objects, row: None)
    monkeypatch.setattr(transfer, "_project", lambda pts, K: (torch.from_numpy(next(calls)), torch.ones(4, dtype=bool)))
    got = transfer._contact_shadow(None, list(range(len(polys))), None, size).numpy()
    assert np.array_equal(got, _contact_loop(polys, size))


@pytest.mark.parametrize("seed", range(3))
def test_recolour_equals_one_image_copy_per_object(seed):
    gen = torch.Generator().manual_seed(seed)
    owner = _blobs(gen, 40, 70, 4)
    out = torch.rand(3, 40, 70, generator=gen)
    source = torch.randint(0, 3, (40, 70), generator=gen).to(torch.uint8)
    recolor = {2: (0.8, 0.1, 0.1), 9: (0.1, 0.1, 0.9), 3: (0.2, 0.7, 0.2)}
    ref_out, ref_src, ref_objects, ref_warn = out, source, {}, []
    for iid, rgb in recolor.items():
        region = owner == int(iid)
        if not bool(region.any()):
            ref_warn.append(f"recolor: object {iid} has no pixels in the picture")
            continue
        colors = ref_out.permute(1, 2, 0)[region]
        new, _, stats = recolor_pixels(colors, tuple(rgb))
        flat = ref_out.permute(1, 2, 0).clone()
        flat[region] = new
        ref_out = flat.permute(2, 0, 1)
        repainted = torch.zeros_like(region)
        repainted[region] = (new != colors).any(1)
        ref_src = torch.where(repainted & (ref_src == INPUT), RECOLORED, ref_src).to(torch.uint8)
        ref_objects.setdefault(int(iid), {}).update({"recolor": {"color": list(rgb), **stats}})
    objects, warnings = {}, []
    got_out, got_src = transfer._recolor(out, source, owner, recolor, objects, warnings)
    assert torch.equal(got_out, ref_out) and torch.equal(got_src, ref_src) and warnings == ref_warn
    assert list(objects) == list(ref_objects)
