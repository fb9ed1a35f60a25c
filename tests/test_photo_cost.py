"""The photo appearance's cost cuts (docs/results/2026-11-29_cpu/session8/photocost/): each faster helper gives what
the code it replaced gave, bit for bit (the replaced code is written out here as the reference)."""

from __future__ import annotations

import math

import pytest
import torch
import torch.nn.functional as F

from sdn3d.editing.apply import Delete, Move, Rotate, apply_edits
from sdn3d.editing.photo import fill as photo_fill
from sdn3d.editing.photo import road as photo_road
from sdn3d.editing.photo.occluders import _extend_upright, _strips, thin_occluders
from sdn3d.editing.photo.recolor import srgb_to_lab
from sdn3d.editing.photo.road import _along, _gather, _trace, ab_length, road_colours, road_lab, road_like
from sdn3d.editing.photo.transfer import PhotoSource, _erode_ids, _first_true, _pyramid, render_photo
from sdn3d.image_ops import dilate_square, id_counts, ids_present, isin_ids
from tests.test_photo import CAR, FAR_CAR, FRAME, INPUT_SIZE, _scene


def _trace_one_pass(pix, unit, valid, steps, limit):
    """_trace as it was: every step of every ray at once."""
    height, width = valid.shape
    pos = pix[:, None, :] + steps[None, :, None] * unit[:, None, :]
    x, y = pos[..., 0].round().long(), pos[..., 1].round().long()
    inside = (x >= 0) & (x < width) & (y >= 0) & (y < height) & (steps[None] <= limit[:, None])
    ok = inside & valid[y.clamp(0, height - 1), x.clamp(0, width - 1)]
    return steps[ok.float().argmax(1)], ok.any(1)


def _rays(seed: int, n: int, height: int, width: int) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    g = torch.Generator().manual_seed(seed)
    valid = torch.rand(height, width, generator=g) > 0.3
    valid[height // 4: 3 * height // 4, width // 5: 4 * width // 5] = False  # a hole the rays must cross
    pix = torch.stack([torch.rand(n, generator=g) * width, torch.rand(n, generator=g) * height], 1).floor()
    angle = torch.rand(n, generator=g) * 6.2832
    return valid, pix, torch.stack([angle.cos(), angle.sin()], 1)


@pytest.fixture(params=["kernel", "torch"])
def ray_path(request, monkeypatch):
    """Each ray helper by the C++ kernel (skipped without a compiler) and by its PyTorch path."""
    if request.param == "torch":
        monkeypatch.setattr(photo_road, "ray_kernel", lambda: None)
    elif photo_road.ray_kernel() is None:
        pytest.skip("no C++ compiler: the ray kernel cannot build")
    return request.param


def test_trace_in_blocks_finds_the_first_valid_step_of_one_pass(ray_path):
    for seed, (height, width) in enumerate([(60, 200), (97, 131), (375, 1242)]):
        valid, pix, unit = _rays(seed, 3000, height, width)
        steps = torch.cat([torch.arange(1, 17), torch.arange(17, 150 + 50 * seed, 2)]).float()
        limit = torch.rand(len(pix), generator=torch.Generator().manual_seed(seed)) * 200
        for lim in (limit, torch.full((len(pix),), float(steps[-1]))):
            want = _trace_one_pass(pix, unit, valid, steps, lim)
            got = _trace(pix, unit, valid, steps, lim)
            assert torch.equal(got[0], want[0]) and torch.equal(got[1], want[1])
        got = _trace(pix, unit, valid, steps, None)  # no limit: the same as a limit at the last step
        assert torch.equal(got[0], want[0]) and torch.equal(got[1], want[1])
        assert bool(want[1].any()) and not bool(want[1].all())  # found and not found both tested


def test_trace_rounds_half_to_even(ray_path):
    # units whose products land on halves (0.5, 2.5, ...: rounded to even, as torch's round; half away from zero
    # fails this), among random ones (a fused multiply-add in the kernel is caught by the _along test below, whose
    # points themselves are compared through the bilinear gather)
    height, width = 64, 4000
    g = torch.Generator().manual_seed(7)
    valid = torch.rand(height, width, generator=g) > 0.6
    halves = torch.tensor([[0.5, 0.5], [-0.5, 0.25], [0.75, -0.5], [1.5, 0.5], [-0.25, -0.75]])
    angle = torch.rand(4000, generator=g) * 6.2832
    unit = torch.cat([halves.repeat(200, 1), torch.stack([angle.cos(), angle.sin()], 1)])
    pix = torch.stack([torch.rand(len(unit), generator=g) * width, torch.rand(len(unit), generator=g) * height], 1)
    pix = pix.floor() + torch.tensor([0.0, 0.0]).where(torch.rand(len(unit), 1, generator=g) < 0.5, 0.5)
    steps = torch.cat([torch.arange(1, 17), torch.arange(17, 61, 2)]).float()
    limit = torch.rand(len(pix), generator=g) * 70
    want = _trace_one_pass(pix, unit, valid, steps, limit)
    got = _trace(pix, unit, valid, steps, limit)
    assert torch.equal(got[0], want[0]) and torch.equal(got[1], want[1])


def test_along_in_one_call_equals_the_loop_over_its_points(ray_path):
    g = torch.Generator().manual_seed(3)
    image = torch.rand(3, 50, 90, generator=g)
    valid = torch.rand(50, 90, generator=g) > 0.3
    start = torch.stack([torch.rand(400, generator=g) * 100 - 5, torch.rand(400, generator=g) * 60 - 5], 1)
    angle = torch.rand(400, generator=g) * 6.2832
    unit = torch.stack([angle.cos(), angle.sin()], 1)
    for span in (1, 2, 12):
        total, count = torch.zeros(3, len(start)), torch.zeros(len(start))
        for k in range(span):  # _along as it was
            q = start + k * unit
            x, y = q[:, 0].round().long(), q[:, 1].round().long()
            ok = (x >= 0) & (x < 90) & (y >= 0) & (y < 50) & valid[y.clamp(0, 49), x.clamp(0, 89)]
            ok = torch.ones_like(ok) if k == 0 else ok
            total += _gather(image, q) * ok
            count += ok
        assert torch.equal(_along(image, valid, start, unit, span), total / count.clamp(min=1))


def test_gather_samples_as_the_grid_made_a_column_at_a_time():
    g = torch.Generator().manual_seed(5)
    for height, width in ((375, 1242), (50, 90), (1, 1)):
        image = torch.rand(3, height, width, generator=g)
        points = torch.stack([torch.rand(20000, generator=g) * (width + 20) - 10,
                              torch.rand(20000, generator=g) * (height + 20) - 10], 1)
        gx = points[:, 0] / max(width - 1, 1) * 2 - 1  # _gather as it was
        gy = points[:, 1] / max(height - 1, 1) * 2 - 1
        grid = torch.stack([gx, gy], 1).view(1, 1, -1, 2)
        want = F.grid_sample(image[None], grid, mode="bilinear", padding_mode="border", align_corners=True)[0, :, 0]
        assert torch.equal(_gather(image, points), want)
        assert torch.equal(_gather(image, points[::2]), want[:, ::2])  # a strided view of the points


def test_ab_length_is_torch_norm_bit_for_bit():
    g = torch.Generator().manual_seed(5)
    lab = srgb_to_lab(torch.rand(20000, 3, generator=g))  # channel-major rows, as road_like reads them
    road = lab.median(0).values
    for ab in (lab[:, 1:], lab[:, 1:] - road[1:], (lab[:, 1:] - road[1:]).view(100, 200, 2),
               lab[:, 1:].double() * 3.7, lab[:, 1:].contiguous()):
        assert torch.equal(ab_length(ab), ab.norm(dim=-1))
    assert ab_length(lab[:, 1:] - road[1:]).dtype == torch.float32


def test_road_helpers_keep_their_answers():
    """road_colours and road_like as they were, with the Lab road.py computes (road_lab, session 9 rot05)."""
    g = torch.Generator().manual_seed(8)
    image = torch.rand(3, 40, 70, generator=g) * 0.2 + 0.4
    ring = torch.zeros(40, 70, dtype=torch.bool)
    ring[5:35, 5:65] = True
    road = road_colours(image, ring)
    flat = image.permute(1, 2, 0).reshape(-1, 3)
    lab = road_lab(flat[ring.view(-1)])
    ab = lab[:, 1:]
    ref = ab[ab.norm(dim=1) < 24.0]
    near = (ab - ref.median(0).values).norm(dim=1) < 12.0
    assert torch.equal(road, lab[near].median(0).values)  # road_colours as it was, with torch's norm
    full = road_lab(flat)
    want = ((full[:, 1:] - road[1:]).norm(dim=1) < 12.0).view(40, 70)
    assert torch.equal(road_like(image, road), want)


def test_id_membership_by_table_is_torch_isin():
    g = torch.Generator().manual_seed(2)
    ids = torch.randint(0, 4, (30, 40), generator=g) * torch.randint(12000, 12010, (30, 40), generator=g)
    wanted = torch.tensor([12003, 0, 5, -2, 12009, 1 << 40])
    assert torch.equal(isin_ids(ids, wanted), torch.isin(ids, wanted))
    assert torch.equal(ids_present(ids, wanted), torch.isin(wanted, ids))
    assert torch.equal(id_counts(ids, wanted), torch.stack([(ids == w).sum() for w in wanted]))
    for odd in (ids - 12005, ids + (1 << 30), ids[:0]):  # negative, huge and no ids: torch.isin itself
        assert torch.equal(isin_ids(odd, wanted), torch.isin(odd, wanted))
        assert torch.equal(ids_present(odd, wanted), torch.isin(wanted, odd))
        assert torch.equal(id_counts(odd, wanted), torch.stack([(odd == w).sum() for w in wanted]))
    assert torch.equal(id_counts(ids, wanted[:0]), torch.zeros(0, dtype=torch.long))
    for layout in (ids.t(), ids.int(), ids[::2, 1::3], ids.to(torch.int16)):  # strided and narrower ids: NumPy's lookup
        assert torch.equal(isin_ids(layout, wanted), torch.isin(layout, wanted))


def test_erode_ids_is_the_max_pool_it_replaced():
    g = torch.Generator().manual_seed(4)
    for ids in (torch.randint(0, 3, (37, 53), generator=g) * 7, torch.zeros(9, 11, dtype=torch.long),
                torch.randint(0, 2, (1, 30), generator=g) * 12004):
        for radius in (0, 1, 2, 3):
            x = ids[None, None].double()
            k = 2 * radius + 1
            hi = F.max_pool2d(F.pad(x, (radius,) * 4, mode="replicate"), k, stride=1)
            lo = -F.max_pool2d(F.pad(-x, (radius,) * 4, mode="replicate"), k, stride=1)
            want = ids if radius == 0 else torch.where((hi == lo)[0, 0], ids, torch.zeros_like(ids))
            assert torch.equal(_erode_ids(ids, radius), want)


def test_first_true_is_argmax_of_the_masks():
    g = torch.Generator().manual_seed(6)
    for s in (1, 2, 5):
        masks = torch.rand(s, 20, 30, generator=g) > 0.7
        assert torch.equal(_first_true(masks), masks.to(torch.uint8).argmax(0))


def test_thin_occluders_on_the_outlines_rows_equal_the_whole_picture():
    ids = torch.zeros(60, 80, dtype=torch.long)
    ids[20:40, 10:70] = 7
    outline = ids.clone()
    image = torch.full((3, 60, 80), 0.6)
    image[:, 20:40, 10:70] = torch.tensor([0.7, 0.2, 0.2])[:, None, None]
    ids[20:40, 38:41] = 0  # a pole across the car, running on above and below it
    image[:, :, 38:41] = 0.1
    found = thin_occluders(image, ids, outline)
    whole = _extend_upright(_strips(image, ids, outline, (outline != 0) & (ids == 0), 0.3, 0.4, 0.08), image, ids,
                            0.08)
    assert torch.equal(found, whole)
    assert int(found.sum()) == 60 * 3


def test_photo_source_keeps_one_pyramid_and_pictures_stay_the_same():
    scene = _scene([CAR, FAR_CAR])
    original = torch.rand(3, INPUT_SIZE[1], INPUT_SIZE[0], generator=torch.Generator().manual_seed(1))
    source = PhotoSource(original, FRAME, scene)
    pyramid = source.pyramid(3)
    assert source.pyramid(3) is pyramid
    assert all(torch.equal(a, b) for a, b in zip(pyramid, _pyramid(source.image, 3), strict=True))
    for ops in ([Move(12001, (50.0, 40.0)), Rotate(12001, math.radians(60))], [Move(12002, (90.0, 35.0))]):
        edited = apply_edits(scene, ops)  # the same picture with the kept source (and its pyramid) as without
        kept = render_photo(original, FRAME, scene, edited, source=source)
        fresh = render_photo(original, FRAME, scene, edited)
        assert torch.equal(kept.image, fresh.image) and torch.equal(kept.source, fresh.source)
        assert bool((kept.source != 0).any())


def test_a_removal_is_made_once_per_source_leftovers_and_vanishing_point_included(monkeypatch):
    """A kept source state makes a removal (its fill, matte, leftover pieces and road vanishing point) once for the
    objects that left and stayed: deleting a car and then turning it draw on the same removal, and the pictures
    equal those of a fresh source state."""
    calls = {"leftover_pieces": 0, "removal_vanishing_point": 0}
    homes = {"leftover_pieces": photo_fill, "removal_vanishing_point": photo_road}  # removal_guides calls them there
    for name in calls:
        def counted(*args, _f=getattr(homes[name], name), _name=name, **kwargs):
            calls[_name] += 1
            return _f(*args, **kwargs)

        monkeypatch.setattr(homes[name], name, counted)
    scene = _scene([CAR, FAR_CAR])
    original = torch.rand(3, INPUT_SIZE[1], INPUT_SIZE[0], generator=torch.Generator().manual_seed(2))
    source = PhotoSource(original, FRAME, scene)
    edits = ([Delete(12001)], [Rotate(12001, math.radians(90))], [Delete(12001)])
    kept = [render_photo(original, FRAME, scene, apply_edits(scene, ops), source=source) for ops in edits]
    assert calls == {"leftover_pieces": 1, "removal_vanishing_point": 1}
    for ops, picture in zip(edits, kept, strict=True):
        fresh = render_photo(original, FRAME, scene, apply_edits(scene, ops))
        assert torch.equal(picture.image, fresh.image) and torch.equal(picture.source, fresh.source)
    assert calls == {"leftover_pieces": 4, "removal_vanishing_point": 4}  # a fresh state makes its own


def _vanishing_point_whole(image, region, K, min_edges=50, max_edges=4000, coherence=0.9, window=7, spread_deg=1.0,
                           forward_snap_deg=0.0):
    """image_vanishing_point on the whole picture: gradients and their coherence everywhere."""
    import math

    import cv2

    from sdn3d.image_ops import luminance

    fx, cx, cy = float(K[0, 0]), float(K[0, 2]), float(K[1, 2])
    y = luminance(image.permute(1, 2, 0).reshape(-1, 3)).view(image.shape[1:]).float().numpy()
    gx = torch.from_numpy(cv2.Sobel(y, cv2.CV_32F, 1, 0, ksize=3))
    gy = torch.from_numpy(cv2.Sobel(y, cv2.CV_32F, 0, 1, ksize=3))
    mag = (gx**2 + gy**2).sqrt()
    use = region & (torch.arange(image.shape[1])[:, None] > cy + 2) & (mag > 0.15)
    if int(use.sum()) < min_edges:
        return None
    jxx, jyy, jxy = (torch.from_numpy(cv2.boxFilter(c.numpy(), -1, (window, window), normalize=False,
                                                    borderType=cv2.BORDER_CONSTANT))
                     for c in (gx * gx, gy * gy, gx * gy))
    use &= ((jxx - jyy).square() + 4 * jxy.square()) / (jxx + jyy).square().clamp(min=1e-12) >= coherence
    if int(use.sum()) < min_edges:
        return None
    ys, xs = use.nonzero(as_tuple=True)
    m = mag[ys, xs]
    if len(m) > max_edges:
        keep = m.topk(max_edges).indices
        ys, xs, m = ys[keep], xs[keep], m[keep]
    tx, ty = -gy[ys, xs] / m, gx[ys, xs] / m
    heading = torch.deg2rad(torch.arange(-70.0, 70.25, 0.5))
    us = cx + fx * torch.tan(heading)
    slanted = ty.abs() > 1e-3
    meets = xs.float() + (cy - ys.float()) * tx / torch.where(slanted, ty, torch.ones_like(ty))
    aim = torch.atan((meets - cx) / fx)
    score = (torch.exp(-0.5 * ((heading[None] - aim[:, None]) / math.radians(spread_deg)).square())
             * (m * slanted)[:, None]).sum(0)
    best = int(score.argmax())
    if abs(float(heading[best])) <= math.radians(forward_snap_deg) + 1e-9:
        best = int(heading.abs().argmin())
    return float(us[best]), cy


def test_vanishing_point_from_the_regions_window_equals_the_whole_picture():
    from sdn3d.road_heading import image_vanishing_point

    g = torch.Generator().manual_seed(9)
    K = torch.tensor([[721.5, 0.0, 609.6], [0.0, 721.5, 172.9], [0.0, 0.0, 1.0]], dtype=torch.float64)
    image = torch.rand(3, 375, 1242, generator=g)
    image[:, 200:, :] = torch.linspace(0, 1, 1242)[None, None, :] * 0.5  # lines to vote
    image[:, 200:, :] += (torch.arange(375 - 200)[:, None] % 7 == 0) * 0.4
    found = 0
    for y0, y1, x0, x1 in [(180, 300, 100, 400), (300, 375, 0, 120), (190, 375, 1100, 1242), (250, 260, 613, 700),
                           (0, 375, 0, 1242), (200, 220, 5, 9)]:
        region = torch.zeros(375, 1242, dtype=torch.bool)
        region[y0:y1, x0:x1] = True
        for max_edges in (4000, 300):
            want = _vanishing_point_whole(image, region, K, max_edges=max_edges, forward_snap_deg=1.0)
            assert image_vanishing_point(image, region, K, max_edges=max_edges, forward_snap_deg=1.0) == want
            found += want is not None
    assert found >= 8
    empty = torch.zeros(375, 1242, dtype=torch.bool)
    assert image_vanishing_point(image, empty, K) is None
    assert image_vanishing_point(image, empty, K, min_edges=0) == _vanishing_point_whole(image, empty, K, min_edges=0)


def test_shadow_bands_on_the_objects_window_equal_the_whole_picture():
    from sdn3d.editing.photo.fill import _bands_in, _shadow_bands  # _bands_in on the whole picture: as it was

    ids = torch.zeros(50, 70, dtype=torch.long)
    ids[10:20, 5:25] = 3
    ids[15:40, 30:60] = 4
    ids[42:50, 0:10] = 5  # reaches the bottom edge
    ids[0:8, 62:70] = 6  # the top and right edges
    for gone in ([3], [4, 5], [3, 4, 5, 6], [6, 9], [4, 3]):
        g = torch.tensor(gone)
        present = g[torch.isin(g, ids)]
        for share in (0.3, 1.0):
            assert torch.equal(_shadow_bands(ids, g, share), _bands_in(ids, present, share))
    assert not bool(_shadow_bands(ids, torch.tensor([9]), 0.3).any())


def test_into_original_converts_only_the_changed_box_as_the_whole_picture_did():
    from sdn3d.editing.photo.transfer import _into_original

    g = torch.Generator().manual_seed(12)
    out = torch.rand(3, 30, 40, generator=g) * 1.4 - 0.2  # outside [0, 1] too: clamped
    changed = torch.zeros(30, 40, dtype=torch.bool)
    changed[5:9, 10:31] = torch.rand(4, 21, generator=g) > 0.5
    for original in (torch.randint(0, 256, (3, 30, 40), dtype=torch.uint8, generator=g),
                     torch.rand(3, 30, 40, generator=g).double()):
        result = out.clamp(0, 1)  # render_photo's conversion as it was
        want = (torch.where(changed[None], (result * 255 + 0.5).floor().clamp(0, 255).to(torch.uint8), original)
                if original.dtype == torch.uint8 else torch.where(changed[None], result.to(original.dtype), original))
        got = _into_original(out, changed, original)
        assert got.dtype == original.dtype and torch.equal(got, want)
        assert torch.equal(_into_original(out, torch.zeros_like(changed), original), original)


# Session 9 (docs/results/2026-11-29_cpu/session9/rotcost/): the rotate edit's cost.


def _dilate_by_opencv(mask, radius):
    """dilate_square as it was: OpenCV's dilation by the whole square at every radius."""
    import cv2
    import numpy as np

    if radius <= 0 or not bool(mask.any()):
        return mask
    kernel = np.ones((2 * radius + 1, 2 * radius + 1), np.uint8)
    return torch.from_numpy(cv2.dilate(mask.numpy().astype(np.uint8), kernel) > 0)


def test_dilate_square_by_running_counts_is_opencvs_dilation(monkeypatch):
    import sdn3d.image_ops as image_ops

    g = torch.Generator().manual_seed(9)
    masks = [torch.rand(h, w, generator=g) < p for h, w, p in ((40, 90, 0.002), (37, 53, 0.05), (1, 30, 0.2),
                                                              (25, 1, 0.3), (60, 70, 0.6))]
    masks.append(torch.zeros(20, 30, dtype=torch.bool))
    corner = torch.zeros(50, 80, dtype=torch.bool)
    corner[0, 79] = corner[49, 0] = corner[20, 40] = True  # on the picture's edges and inside
    masks.append(corner)
    for threshold in (image_ops.DILATE_COUNTS_MIN, 0):  # 0: the counts at every radius
        monkeypatch.setattr(image_ops, "DILATE_COUNTS_MIN", threshold)
        for mask in masks:
            for radius in (0, 1, 2, 5, 17, 49, 64, 79, 200):
                assert torch.equal(dilate_square(mask, radius), _dilate_by_opencv(mask, radius)), (mask.shape, radius)
    monkeypatch.setattr(image_ops, "DILATE_COUNTS_MIN", 48)
    big = torch.zeros(375, 1242, dtype=torch.bool)
    big[150:300, 500:700] = torch.rand(150, 200, generator=g) < 0.9
    for radius in (49, 300, 1016):  # a car's hole grown by the radii the rays' fill uses at 1242x375
        assert torch.equal(dilate_square(big, radius), _dilate_by_opencv(big, radius))


def _road_picture(height: int, width: int, seed: int) -> torch.Tensor:
    """A grey road with grain, a green verge on the left, white dashes and a darker shade: road-like and not."""
    g = torch.Generator().manual_seed(seed)
    image = 0.45 + 0.04 * torch.randn(3, height, width, generator=g)
    image[:, :, : width // 6] = torch.tensor([0.2, 0.5, 0.15])[:, None, None]
    image[:, height // 2:, width // 2: width // 2 + 3] = 0.9
    image[:, : height // 3, width // 3: width // 2] *= 0.5
    return image.clamp(0, 1)


def _road_like_as_it_was(image, road, tolerance=12.0, min_light=0.0, within=None):
    out = torch.zeros(image.shape[1:], dtype=torch.bool)
    y0, y1, x0, x1 = 0, image.shape[1], 0, image.shape[2]
    if within is not None:
        if not bool(within.any()):
            return out
        ys, xs = within.any(1).nonzero().flatten(), within.any(0).nonzero().flatten()
        y0, y1, x0, x1 = int(ys[0]), int(ys[-1]) + 1, int(xs[0]), int(xs[-1]) + 1
    crop = image[:, y0:y1, x0:x1]
    lab = road_lab(crop.permute(1, 2, 0).reshape(-1, 3))
    ok = (ab_length(lab[:, 1:] - road[1:]) < tolerance) & (lab[:, 0] >= min_light * road[0])
    out[y0:y1, x0:x1] = ok.view(crop.shape[1:])
    return out


def test_road_colours_and_road_like_read_the_same_pixels_from_a_boxed_or_strided_picture():
    from sdn3d.editing.photo.road import _box

    image = _road_picture(60, 240, 3)
    g = torch.Generator().manual_seed(4)
    for step in (1, 3):  # road_haze reads every third column of a wide picture
        img = image[:, :, ::step]
        for p in (0.0, 0.001, 0.3, 1.0):
            within = torch.rand(60, 240, generator=g)[:, ::step] < p
            rows, cols = within.nonzero(as_tuple=True)
            want = None if not len(rows) else (int(rows.min()), int(rows.max()) + 1, int(cols.min()),
                                                int(cols.max()) + 1)
            assert _box(within) == want
            pix = img.permute(1, 2, 0).reshape(-1, 3)[within.reshape(-1)]  # road_colours' pixels as they were
            lab = road_lab(pix) if len(pix) else None
            road = road_colours(img, within)
            if road is not None:
                ref = lab[:, 1:][ab_length(lab[:, 1:]) < 24.0]
                near = ab_length(lab[:, 1:] - ref.median(0).values) < 12.0
                assert torch.equal(road, lab[near].median(0).values)
            road = srgb_to_lab(torch.tensor([[0.45, 0.45, 0.45]]))[0] if road is None else road
            for min_light in (0.0, 0.8):
                assert torch.equal(road_like(img, road, min_light=min_light, within=within),
                                   _road_like_as_it_was(img, road, min_light=min_light, within=within))
    odd = image[:, :, :-1][:, :, ::3]  # 239 columns: the old row view of a strided ring failed here
    ring = torch.ones(60, 239, dtype=torch.bool)[:, ::3]
    assert road_colours(odd, ring) is not None


def _matched_weight_as_it_was(image, valid, values, grains, ys, xs, default):
    from sdn3d.editing.photo.road import GRAIN_WEIGHTS, _luma_laplacian

    height, width = valid.shape
    hole = torch.zeros_like(valid)
    hole[ys, xs] = True
    ring = dilate_square(hole, 40) & ~dilate_square(hole, 8) & valid
    road = road_colours(image, ring)
    if road is None:
        return default
    around = ring & road_like(image, road, within=ring)
    if int(around.sum()) < 50:
        return default
    y0, y1 = max(int(ys.min()) - 41, 0), min(int(ys.max()) + 42, height)
    x0, x1 = max(int(xs.min()) - 41, 0), min(int(xs.max()) + 42, width)
    target = float(_luma_laplacian(image[:, y0:y1, x0:x1].float())[around[y0:y1, x0:x1]].mean())
    inside = (~dilate_square(~hole, 1))[ys, xs]
    if int(inside.sum()) < 50:
        return default
    iy, ix = ys[inside], xs[inside]
    y0, y1 = max(int(iy.min()) - 1, 0), min(int(iy.max()) + 2, height)
    x0, x1 = max(int(ix.min()) - 1, 0), min(int(ix.max()) + 2, width)
    box = (ys >= y0) & (ys < y1) & (xs >= x0) & (xs < x1)
    values, grains, ys, xs, inside = values[:, box], grains[:, box], ys[box], xs[box], inside[box]
    crop = image[:, y0:y1, x0:x1].float().clone()
    best, gap = default, math.inf
    for w in GRAIN_WEIGHTS:
        filled = (values + w * grains).clamp(0, 1)
        crop[:, ys - y0, xs - x0] = filled
        like = inside.clone()
        like[inside] = road_like(filled[:, inside, None], road)[:, 0]
        if int(like.sum()) < 50:
            continue
        level = float(_luma_laplacian(crop)[ys[like] - y0, xs[like] - x0].mean())
        if abs(level - target) < gap:
            best, gap = w, abs(level - target)
    return best


def test_matched_weight_from_the_holes_box_is_the_whole_pictures():
    from sdn3d.editing.photo.road import _matched_weight

    image = _road_picture(90, 200, 5)
    g = torch.Generator().manual_seed(6)
    picked = set()
    for box in ((20, 60, 60, 130), (0, 30, 150, 200), (50, 90, 0, 70), (40, 48, 90, 98)):  # inside, on the edges
        hole = torch.zeros(90, 200, dtype=torch.bool)
        hole[box[0]:box[1], box[2]:box[3]] = torch.rand(box[1] - box[0], box[3] - box[2], generator=g) < 0.97
        valid = ~hole
        ys, xs = hole.nonzero(as_tuple=True)
        values = image[:, ys, xs].flip(1) * 0.9 + 0.05  # a plausible smooth fill and its grain
        for scale in (0.0, 0.01, 0.05, 0.2):
            grains = scale * torch.randn(3, len(ys), generator=g)
            want = _matched_weight_as_it_was(image, valid, values, grains, ys, xs, 1.0)
            assert _matched_weight(image, valid, values, grains, ys, xs, 1.0) == want
            picked.add(want)
    assert len(picked) >= 3  # several weights chosen, the default among the others


def _road_haze_as_it_was(image, valid, hole, horizon, airlight=0.25):
    from sdn3d.editing.photo import road as rd

    height, width = hole.shape
    ys, xs = hole.nonzero(as_tuple=True)
    extent = max(int(ys.max() - ys.min()), int(xs.max() - xs.min()), 20)
    rows = torch.arange(height, dtype=torch.float32)
    step = max(1, width // rd.HAZE_COLUMNS)
    region = (dilate_square(hole, extent) & valid & (rows > horizon + 1)[:, None])[:, ::step]
    image = image[:, :, ::step]
    road = road_colours(image, region)
    if road is None:
        return None
    like = region & road_like(image, road, within=region)
    count = like.sum(1)
    use = (count >= rd.HAZE_MIN_PIXELS).nonzero().flatten()
    if len(use) < rd.HAZE_MIN_ROWS:
        return None
    cols = like.any(0).nonzero().flatten()
    band = image[:, use][:, :, int(cols[0]):int(cols[-1]) + 1].float()
    keep = like[use][:, int(cols[0]):int(cols[-1]) + 1]
    med = torch.where(keep[None], band, torch.full_like(band, float("nan"))).nanmedian(2).values.double()
    weight = count[use].double().sqrt()
    depth = (rows[use].double() - horizon).clamp(min=1.0)
    best, fit = math.inf, None
    for k in rd.HAZE_DEPTHS:
        x = torch.exp(-k / depth)
        design = torch.stack([torch.ones_like(x), x], 1) * weight[:, None]
        sol = torch.linalg.lstsq(design, (med * weight).T).solution
        err = float(((design @ sol - (med * weight).T) ** 2).sum())
        if err < best:
            best, fit = err, (k, sol)
    k, sol = fit
    if float(sol[1].mean()) > 0:
        return None
    own = sol[0] + sol[1]
    if float(own.min()) < -rd.HAZE_RANGE_SLACK or float(own.max()) > 1 + rd.HAZE_RANGE_SLACK:
        return None
    if airlight < 1:
        band = max(2, height // rd.HAZE_FAR_ROWS)
        far = (valid & ((rows - horizon).abs() <= band)[:, None])[:, ::step]
        if int(far.sum()) < rd.HAZE_FAR_PIXELS:
            return None
        seen = image[:, far].double().median(1).values
        if float((sol[0] - seen).abs().max()) > airlight:
            return None
    below = (rows.double() - horizon).clamp(min=1.0)
    return (sol[0][:, None] + sol[1][:, None] * torch.exp(-k / below)[None]).float()


def test_road_haze_with_its_band_sliced_first_is_the_fit_it_was():
    from sdn3d.editing.photo.road import road_haze

    g = torch.Generator().manual_seed(7)
    fits = 0
    for width in (160, 1200):  # 1200: every third column read
        rows = torch.arange(96, dtype=torch.float32)[:, None]
        road = 0.8 + (0.4 - 0.8) * torch.exp(-8.0 / (rows - 30.0).clamp(min=1.0))  # fog towards the horizon
        image = (road.expand(96, width)[None].repeat(3, 1, 1) + 0.01 * torch.randn(3, 96, width, generator=g))
        image[:, :31] = 0.8
        image = image.clamp(0, 1)
        hole = torch.zeros(96, width, dtype=torch.bool)
        hole[26:60, width // 2 - 15: width // 2 + 15] = True
        for airlight in (0.25, 1.0):
            want = _road_haze_as_it_was(image, ~hole, hole, 30.0, airlight)
            got = road_haze(image, ~hole, hole, 30.0, airlight)
            assert (got is None) == (want is None) and (got is None or torch.equal(got, want))
            fits += want is not None
    assert fits >= 2


def _lab_as_it_was(rgb):
    from sdn3d.editing.photo.recolor import _RGB_TO_XYZ, _WHITE

    image = rgb.float().clamp(0, 1).T[:, :, None]
    lin = torch.where(image > 0.04045, torch.pow(((image + 0.055).clamp(min=0.0) / 1.055), 2.4), image / 12.92)
    xyz = torch.einsum("oi, ...ihw -> ...ohw", torch.tensor(_RGB_TO_XYZ, dtype=lin.dtype), lin)
    xyz = torch.div(xyz, torch.tensor(_WHITE, dtype=xyz.dtype)[..., :, None, None])
    f = torch.where(xyz > 0.008856, torch.pow(xyz.clamp(min=0.008856), 1 / 3.0), 7.787 * xyz + 4.0 / 29.0)
    x, y, z = f[..., 0, :, :], f[..., 1, :, :], f[..., 2, :, :]
    return torch.stack([(116.0 * y) - 16.0, 500.0 * (x - y), 200.0 * (y - z)], dim=-3)[:, :, 0].T


def test_lab_with_operations_in_place_is_the_lab_it_was_in_every_layout():
    g = torch.Generator().manual_seed(10)
    picture = torch.rand(3, 70, 130, generator=g) * 1.2 - 0.1  # out of range too: clamped
    layouts = [torch.rand(n, 3, generator=g) for n in (1, 5, 17, 33, 1001)]
    layouts += [picture.permute(1, 2, 0).reshape(-1, 3),  # road_like's box, a view of channel-major rows
                picture[:, 3:61, 7:120].permute(1, 2, 0).reshape(-1, 3),
                picture.reshape(3, -1)[:, :977, None].permute(1, 2, 0).reshape(-1, 3),  # _matched_weight's pixels
                picture[:, picture[0] > 0.5].T.contiguous(), picture.double().reshape(3, -1).T[:500]]
    for rgb in layouts:
        got, want = srgb_to_lab(rgb), _lab_as_it_was(rgb)
        assert torch.equal(got, want) and got.stride() == want.stride()


def test_part_map_at_covered_pixels_is_the_whole_maps_there():
    from sdn3d.editing.photo.transfer import _part_map

    scene = _scene([CAR, FAR_CAR])
    original = torch.rand(3, INPUT_SIZE[1], INPUT_SIZE[0], generator=torch.Generator().manual_seed(2))
    source = PhotoSource(original, FRAME, scene)
    covered = source.raster.frags.covered()
    assert len(covered) > 100
    for at in (covered, covered[::7].flip(0), covered[:0]):
        got = _part_map(source.raster, scene.objects, source.bank, at)
        assert got.dtype == torch.long and torch.equal(got, source.parts[at])
    assert len(set(source.parts[covered].tolist())) >= 3  # several parts looked up


def test_surface_points_selected_are_those_computed_on_the_selected_pixels():
    from sdn3d.editing.photo.transfer import _surface, _surface_points

    scene = _scene([CAR, FAR_CAR])
    original = torch.rand(3, INPUT_SIZE[1], INPUT_SIZE[0], generator=torch.Generator().manual_seed(4))
    raster = PhotoSource(original, FRAME, scene).raster
    pix = raster.frags.covered()
    mesh, vid, bary, normal, tri, point = _surface_points(raster, pix)
    assert all(torch.equal(a, b) for a, b in zip(_surface(raster, pix), (mesh, vid, bary, normal), strict=True))
    g = torch.Generator().manual_seed(5)
    for k in (torch.arange(len(pix)), (torch.rand(len(pix), generator=g) < 0.37).nonzero().flatten(),
              torch.arange(len(pix) - 5, len(pix))):
        want_tri = raster.verts[mesh[k][:, None], vid[k]]  # as _draw and _part_examples computed them after selecting
        assert torch.equal(tri[k], want_tri)
        assert torch.equal(point[k], (bary[k][..., None] * want_tri).sum(1))


def test_column_median_is_torch_median():
    from sdn3d.editing.photo import road as rd

    g = torch.Generator().manual_seed(11)
    for n in (1, 2, 7, 8192, 8193, 12000):
        for x in (torch.rand(n, 3, generator=g), torch.randint(0, 5, (n, 2), generator=g).float(),  # many ties
                  srgb_to_lab(torch.rand(n, 3, generator=g))[:, 1:], torch.randn(n, 3, generator=g).double()):
            got = rd._column_median(x)
            assert got.dtype == x.dtype and torch.equal(got, x.median(0).values), (n, x.dtype)
    assert rd.MEDIAN_NUMPY_MIN <= 8193  # the NumPy path was tested


def test_row_spans_combined_column_by_column_are_the_reductions_they_replaced():
    from sdn3d.render.rasterize import _INSIDE_EPS, _row_spans

    g = torch.Generator().manual_seed(12)
    n = 5000
    a, b, c = (torch.randn(n, 3, generator=g, dtype=torch.float64) for _ in range(3))
    a[torch.rand(n, 3, generator=g) < 0.2] = 0.0  # edges parallel to the rows
    a[:50] = 0.0
    b[:50] = 0.0
    c[:25] = -1.0  # no edge bounds u: feasible
    c[25:50] = 1.0  # infeasible on every row
    rows = torch.randint(-5, 40, (n,), generator=g).double()
    c *= 30.0
    for width in (1, 37, 1242):
        rhs = -_INSIDE_EPS - b * rows.unsqueeze(1) - c  # _row_spans as it was
        bound = rhs / torch.where(a == 0, torch.ones_like(a), a)
        inf = torch.full_like(bound, float("inf"))
        lower = torch.where(a > 0, bound, -inf).amax(1).clamp(-1.0, width)
        upper = torch.where(a < 0, bound, inf).amin(1).clamp(-1.0, width)
        feasible = torch.where(a == 0, rhs <= 0, torch.ones_like(a, dtype=torch.bool)).all(1)
        first = torch.ceil(lower).clamp(min=0).long()
        count = (torch.floor(upper).clamp(max=width - 1).long() - first + 1).clamp(min=0) * feasible
        got = _row_spans(a, b, c, rows, width)
        assert torch.equal(got[0], first) and torch.equal(got[1], count)
        assert bool((count > 0).any()) and bool((count == 0).any()) and int(feasible.sum()) < n


def test_raster_ids_from_a_table_are_the_where_they_replaced():
    from sdn3d.editing.photo.transfer import _raster_ids

    scene = _scene([CAR, FAR_CAR])
    original = torch.rand(3, INPUT_SIZE[1], INPUT_SIZE[0], generator=torch.Generator().manual_seed(6))
    raster = PhotoSource(original, FRAME, scene).raster
    mesh = raster.frags.in_image(raster.frags.pix_to_mesh, -1)[0]
    want = torch.where(mesh >= 0, scene.objects.instance_id[raster.rows[mesh.clamp(min=0)]], torch.zeros_like(mesh))
    got = _raster_ids(raster, scene.objects)
    assert got.dtype == want.dtype and torch.equal(got, want)
    assert len(got.unique()) == 3  # both cars and no car



def test_heading_votes_within_reach_are_the_whole_expression_bit_for_bit():
    from sdn3d.road_heading import VOTE_REACH_SPREADS, _heading_votes

    # exp gives the same bits at any position of a tensor (vector lanes, the scalar tail, strided), which the banded
    # votes rely on: on random arguments of the votes' range and on every float32 where the results turn subnormal
    g = torch.Generator().manual_seed(0)
    x = torch.cat([torch.empty(200_000).uniform_(-130.0, 0.0, generator=g),
                   -torch.arange(int(torch.tensor(87.0).view(torch.int32)), int(torch.tensor(104.0).view(torch.int32)),
                                 37, dtype=torch.int32).view(torch.float32)])
    whole = torch.exp(x)
    assert torch.equal(whole, torch.exp(torch.stack([x, x], 1)[:, 0]))
    assert torch.equal(whole[:70_000], torch.cat([torch.exp(c) for c in x[:70_000].split(7)]))
    assert float(torch.exp(torch.tensor(-0.5 * (VOTE_REACH_SPREADS - 0.01) ** 2))) == 0.0
    heading = torch.deg2rad(torch.arange(-70.0, 70.25, 0.5))
    for seed, (n, spread_deg, scatter_deg) in enumerate([(4000, 1.0, 20.0), (333, 1.0, 80.0), (50, 3.0, 5.0),
                                                         (7, 0.3, 90.0), (0, 1.0, 1.0)]):
        g = torch.Generator().manual_seed(seed)
        aim = torch.deg2rad(torch.randn(n, generator=g) * scatter_deg)
        if n > 10:
            aim[:3] = torch.deg2rad(torch.tensor([-70.0, 70.0, 89.0]))  # on the first and last headings, far outside
        spread = math.radians(spread_deg)
        expected = torch.exp(-0.5 * ((heading[None] - aim[:, None]) / spread).square())
        assert torch.equal(_heading_votes(heading, aim, spread), expected)
    aim = torch.tensor([0.1, float("nan")])
    torch.testing.assert_close(_heading_votes(heading, aim, 0.02),
                               torch.exp(-0.5 * ((heading[None] - aim[:, None]) / 0.02).square()), rtol=0, atol=0,
                               equal_nan=True)


def test_masked_median_is_torch_median_of_the_selection():
    from sdn3d.editing.photo.road import MEDIAN_NUMPY_MIN, _masked_median

    g = torch.Generator().manual_seed(0)
    for steps, (height, width, share) in [(0, (375, 1242, 0.6)), (8, (375, 1242, 0.6)), (0, (40, 60, 0.5)),
                                          (0, (10, 10, 0.01)), (0, (90, 200, 1.0))]:
        x = torch.rand(height, width, generator=g).square()
        if steps:
            x = (x * steps).round() / steps  # many equal values
        mask = torch.rand(height, width, generator=g) < share
        mask.view(-1)[0] = True
        assert _masked_median(x, mask) == float(x[mask].median())
    x = torch.rand(375, 1242, generator=g)
    mask = torch.rand(375, 1242, generator=g) < 0.5
    assert int(mask.sum()) >= MEDIAN_NUMPY_MIN  # the NumPy path
    x[mask.nonzero()[0, 0], mask.nonzero()[0, 1]] = float("nan")
    assert math.isnan(_masked_median(x, mask))


def test_upsample_ids_by_numpys_take_is_the_advanced_indexing_it_replaced():
    from sdn3d.editing.frame import PixelFrame, upsample_ids

    def reference(values, transform):  # upsample_ids as it was
        (sx, sy), (left, top) = transform.scale, transform.offset
        w_in, h_in = transform.input_size
        h, w = values.shape
        j = torch.floor((torch.arange(w_in, dtype=torch.float64) + 0.5) * sx - left).long()
        i = torch.floor((torch.arange(h_in, dtype=torch.float64) + 0.5) * sy - top).long()
        ok = ((i >= 0) & (i < h))[:, None] & ((j >= 0) & (j < w))[None, :]
        out = values.cpu()[i.clamp(0, h - 1)][:, j.clamp(0, w - 1)]
        return torch.where(ok, out, torch.zeros_like(out))

    g = torch.Generator().manual_seed(3)
    ids = torch.randint(0, 30000, (192, 624), generator=g)
    for frame in (PixelFrame((1242, 375), (624, 192)), PixelFrame((300, 100), (128, 64), (160, 64), (20, 0)),
                  PixelFrame((1242, 375), (624, 192), (700, 211), (40, 9))):
        values = ids[:frame.working_size[1], :frame.working_size[0]]  # a strided view, as a crop of a map is
        for v in (values, values.int(), values > 15000):
            assert torch.equal(upsample_ids(v, frame), reference(v, frame))


def _lab_requests(seed: int, height: int, width: int):
    """A mixed sequence of :class:`PictureLab` requests: sparse and dense masks (also on every third column) and boxes,
    overlapping, so both of its conversion paths (selected pixels, the whole box) meet pixels already converted."""
    g = torch.Generator().manual_seed(seed)
    for _ in range(12):
        kind = int(torch.randint(3, (1,), generator=g))
        y0, x0 = (int(v) for v in (torch.randint(height, (1,), generator=g), torch.randint(width, (1,), generator=g)))
        y1 = y0 + 1 + int(torch.randint(height - y0, (1,), generator=g))
        x1 = x0 + 1 + int(torch.randint(width - x0, (1,), generator=g))
        if kind == 0:
            yield "box", (y0, y1, x0, x1)
        else:
            step = 1 if kind == 1 else 3
            p = (0.0, 0.02, 0.4, 0.9, 1.0)[int(torch.randint(5, (1,), generator=g))]
            mask = torch.zeros(height, width, dtype=torch.bool)
            mask[y0:y1, x0:x1] = torch.rand(y1 - y0, x1 - x0, generator=g) < p
            yield "pixels", (mask[:, ::step], step)


def test_picture_lab_is_road_lab_of_the_same_pixels_in_any_order_of_use():
    from sdn3d.editing.photo.road import PictureLab

    image = _road_picture(60, 241, 3)
    image[:, :20, :30] = torch.randint(256, (3, 20, 30), generator=torch.Generator().manual_seed(2)) / 255.0
    image[:, 20:22, :4] = torch.tensor([0.0, 1.0, 0.04045])[:, None, None]  # the ends and sRGB's knee
    for seed in range(4):
        lab = PictureLab(image)
        for kind, args in _lab_requests(seed, 60, 241):
            if kind == "box":
                y0, y1, x0, x1 = args
                got = lab.box(*args)
                want = road_lab(image[:, y0:y1, x0:x1].permute(1, 2, 0).reshape(-1, 3))
            else:
                mask, step = args
                got = lab.pixels(mask, step)
                want = road_lab(image[:, :, ::step][:, mask].T.contiguous())
            assert torch.equal(got, want) and got.shape == want.shape
            assert got.stride() == want.stride() or got.numel() == 0  # the road tests' norms depend on the layout
        assert 0 < int(lab._done.sum()) < lab._done.size  # some pixels, not all, were converted
    levels = torch.randint(256, (60, 241, 3), dtype=torch.uint8, generator=torch.Generator().manual_seed(5))
    levels = levels.permute(2, 0, 1)  # a decoded picture's channel-last memory, as the input arrives
    levels[:, :2, :128] = torch.arange(256, dtype=torch.uint8).view(2, 128)  # every level
    eight_bit = levels.float() / 255  # as PhotoSource makes its image
    for seed in range(3):  # the levels' linear RGB looked up: still road_lab's bits
        lab = PictureLab(eight_bit, levels)
        for kind, args in _lab_requests(10 + seed, 60, 241):
            if kind == "box":
                y0, y1, x0, x1 = args
                want = road_lab(eight_bit[:, y0:y1, x0:x1].permute(1, 2, 0).reshape(-1, 3))
                assert torch.equal(lab.box(*args), want)
            else:
                mask, step = args
                assert torch.equal(lab.pixels(mask, step), road_lab(eight_bit[:, :, ::step][:, mask].T.contiguous()))
    with pytest.raises(ValueError, match="levels"):
        PictureLab(eight_bit, levels.float())
    with pytest.raises(ValueError, match="mask"):
        PictureLab(image).pixels(torch.ones(60, 241, dtype=torch.bool), 3)
    with pytest.raises(ValueError, match="float32"):
        PictureLab(image.double())


def test_removal_road_tests_with_the_pictures_lab_are_those_without():
    from sdn3d.editing.photo.road import PictureLab, _road_around, ray_fill, shadowed_road

    image = _road_picture(90, 200, 5)
    hole = torch.zeros(90, 200, dtype=torch.bool)
    hole[40:70, 80:120] = True
    ring = dilate_square(hole, 30) & ~dilate_square(hole, 6)
    lab = PictureLab(image)
    road = road_colours(image, ring, lab=lab)
    assert road is not None and torch.equal(road, road_colours(image, ring))
    near = dilate_square(hole, 40)
    lit = near & ~dilate_square(hole, 3)
    assert torch.equal(shadowed_road(image, road, near, lit, lab=lab), shadowed_road(image, road, near, lit))
    for step in (1, 3):
        got, want = _road_around(image[:, :, ::step], ring[:, ::step], lab=lab, step=step), \
            _road_around(image[:, :, ::step], ring[:, ::step])
        assert torch.equal(got[0], want[0]) and torch.equal(got[1], want[1])
    kwargs = dict(match_grain=True, marks=0.2, haze=1.0, road=road, verge="road", ground_row=30.0)
    got, want = ray_fill(image, hole, (100.0, 10.0), lab=PictureLab(image), **kwargs), \
        ray_fill(image, hole, (100.0, 10.0), **kwargs)
    assert torch.equal(got[0], want[0]) and torch.equal(got[1], want[1])
    with pytest.raises(ValueError, match="another picture"):
        road_colours(image.clone(), ring, lab=lab)


def test_photo_source_keeps_one_lab_of_its_input_and_deletes_draw_the_same():
    from sdn3d.editing.ops import Delete

    scene = _scene([CAR, FAR_CAR])
    original = torch.rand(3, INPUT_SIZE[1], INPUT_SIZE[0], generator=torch.Generator().manual_seed(1))
    source = PhotoSource(original, FRAME, scene)
    lab = source.lab()
    assert source.lab() is lab and lab.image is source.image
    for ops in ([Delete(12001)], [Delete(12002)], [Delete(12001), Delete(12002)]):
        edited = apply_edits(scene, ops)
        kept = render_photo(original, FRAME, scene, edited, source=source)
        fresh = render_photo(original, FRAME, scene, edited)
        assert torch.equal(kept.image, fresh.image) and torch.equal(kept.source, fresh.source)
    assert bool(lab._done.any())  # the deletes' road tests read it
    other = original.flip(2)  # another input: another source, whose Lab is its own picture's
    with pytest.raises(ValueError, match="PhotoSource serves one"):
        source.check(other, scene, FRAME, source.settings)
    box = PhotoSource(other, FRAME, scene).lab().box(0, 20, 0, 40)
    assert torch.equal(box, road_lab(other[:, :20, :40].permute(1, 2, 0).reshape(-1, 3)))
    eight_bit = (original * 255).round().to(torch.uint8)  # an 8-bit input: its levels' linear RGB looked up
    source = PhotoSource(eight_bit, FRAME, scene)
    assert source.lab()._levels is not None
    edited = apply_edits(scene, [Delete(12001)])
    kept = render_photo(eight_bit, FRAME, scene, edited, source=source)
    fresh = render_photo(eight_bit, FRAME, scene, edited, source=PhotoSource(eight_bit, FRAME, scene, max_fills=0))
    assert torch.equal(kept.image, fresh.image)
    assert torch.equal(source.lab().box(0, 128, 0, 256), road_lab(source.image.permute(1, 2, 0).reshape(-1, 3)))


def _dark_car_tyres_as_it_was(image, ids, parts, iid):
    """transfer._dark_car_tyres as it was: its tests over the whole picture."""
    from sdn3d.editing.photo.recolor import DARK_PAINT_L, body_paint
    from sdn3d.editing.photo.transfer import _tyres_in_picture
    from sdn3d.meshes.parts import Part

    flat = image.permute(1, 2, 0).reshape(-1, 3)
    car = ids == iid
    body_pix = (car.view(-1) & (parts == int(Part.BODY))).nonzero().flatten()
    if len(body_pix) < 8:
        return None
    body_lab = srgb_to_lab(flat[body_pix].double())
    paint_light = float(body_lab[:, 0].median())
    if paint_light >= DARK_PAINT_L or body_paint(body_lab)[1]:
        return None
    tyres, freed, wheel_at, wheels = _tyres_in_picture(flat, car, parts.view(ids.shape), paint_light)
    wheel_at = wheel_at.view(-1, 2)
    moved = torch.isfinite(wheel_at[:, 0]).nonzero().flatten()
    return tyres.view(-1).nonzero().flatten(), freed.view(-1).nonzero().flatten(), moved, wheel_at[moved], wheels


def test_dark_car_tyres_found_in_the_cars_box_are_the_whole_pictures():
    """The black car with a misplaced wheel (test_photo_realparts) at several places of a larger picture, beside a
    light car and among other ids: the same tyre, freed and moved indices, moved points and wheel ellipses (and None
    for the light car, an absent id and a car of 5 body pixels) as the whole picture's tests gave."""
    from sdn3d.editing.photo.transfer import _dark_car_tyres
    from sdn3d.meshes.parts import Part
    from tests.test_photo_realparts import _black_car_with_a_misplaced_wheel

    car_image, whole, car_parts, _ = _black_car_with_a_misplaced_wheel()
    # and the car cut to the columns of its real and template wheels: both reach its box's left and right edges
    narrow = whole & (torch.arange(100)[None, :] >= 37) & (torch.arange(100)[None, :] < 70)
    g = torch.Generator().manual_seed(6)
    found = []
    for y0, x0, mask in ((0, 0, whole), (17, 41, whole), (40, 60, whole), (0, 0, narrow), (23, 57, narrow)):
        image = torch.rand(3, 100, 160, generator=g)
        ids = torch.zeros(100, 160, dtype=torch.long)
        parts = torch.full((100, 160), -1, dtype=torch.long)
        image[:, y0:y0 + 60, x0:x0 + 100] = torch.where(mask[None], car_image, image[:, y0:y0 + 60, x0:x0 + 100])
        ids[y0:y0 + 60, x0:x0 + 100][mask] = 5
        parts[y0:y0 + 60, x0:x0 + 100][mask] = car_parts[mask].long()
        light = (ids == 0) & (torch.rand(100, 160, generator=g) < 0.3)
        ids[light], parts[light] = 9, int(Part.BODY)
        image[:, light] = 0.8
        tiny = (ids == 0).nonzero()[:5]
        ids[tiny[:, 0], tiny[:, 1]], parts[tiny[:, 0], tiny[:, 1]] = 11, int(Part.BODY)
        for iid in (5, 9, 11, 3):
            got = _dark_car_tyres(image, ids, parts.view(-1), iid)
            want = _dark_car_tyres_as_it_was(image, ids, parts.view(-1), iid)
            assert (got is None) == (want is None), iid
            if want is not None:
                found.append(mask is narrow)
                assert all(torch.equal(a, b) for a, b in zip(got, want, strict=True))
                assert len(want[0]) > 20 and len(want[1]) > 20
    assert found == [False] * 3 + [True] * 2  # the black car found at each place; the others are None


def _grow_as_it_was(own, before, after, origin, stays, transform, raster_ids=None, vis_ids=None, min_seen=0):
    """transfer._grow as it was: its labels upsampled and compared over the whole picture."""
    from sdn3d.editing.frame import upsample_ids
    from sdn3d.editing.photo.transfer import _first_true

    rows = stays.nonzero().flatten()
    if not len(rows):
        return own, []
    gained = after.mask[rows] & ~before.mask[origin[rows]]
    grew = gained.flatten(1).any(1)
    if vis_ids is not None and min_seen > 0 and bool(grew.any()):
        grew &= id_counts(vis_ids, after.instance_id[rows]) >= min_seen
    if not bool(grew.any()):
        return own, []
    rows, gained = rows[grew], gained[grew]
    first = _first_true(gained)
    labels = torch.where(gained.any(0), after.instance_id[rows][first], torch.zeros_like(first))
    up = upsample_ids(labels.to(after.instance_id.dtype), transform)
    if raster_ids is not None and min_seen > 0:
        up = torch.where(raster_ids == up, torch.zeros_like(up), up)
    new = (up != 0) & (own == 0)
    own = torch.where(new, up.to(own.dtype), own)
    drawn = torch.isin(after.instance_id[rows], up[new].unique())
    return own, rows[drawn].tolist()


def test_grow_in_the_labels_window_is_the_whole_pictures():
    """Objects gaining small blobs of pixels (at the working image's corners and edges too, on frames with and
    without a crop): the same map and grown rows as the whole picture's passes gave, with and without the fitted
    silhouettes and the least seen pixels; the window's upsampled labels are the whole map's there and it is tight
    (every edge row and column of it holds a pixel of the box, and the whole map is 0 outside it)."""
    from types import SimpleNamespace

    from sdn3d.editing.frame import PixelFrame, input_window, upsample_ids
    from sdn3d.editing.photo.transfer import _grow

    g = torch.Generator().manual_seed(8)
    for frame in (PixelFrame((125, 41), (60, 20)), PixelFrame((1242, 375), (624, 192)), PixelFrame((97, 61), (40, 30))):
        w, h = frame.working_size
        w_in, h_in = frame.input_size
        for trial in range(6):
            ids = torch.tensor([3, 5, 7, 8])
            before = SimpleNamespace(instance_id=ids, mask=torch.rand(4, h, w, generator=g) > 0.8)
            after_mask = before.mask.clone()
            for a in range(4):  # a blob gained by each, somewhere (a corner or an edge on some trials)
                y, x = int(torch.randint(0, h, (1,), generator=g)), int(torch.randint(0, w, (1,), generator=g))
                if trial == 1:
                    y, x = (0, 0) if a % 2 else (h - 1, w - 1)
                after_mask[a, max(y - 2, 0):y + 3, max(x - 3, 0):x + 2] = True
            if trial == 2:
                after_mask[1:] = before.mask[1:]  # one object grows alone
            if trial == 3:
                after_mask = before.mask.clone()  # nothing gained
            after = SimpleNamespace(instance_id=ids, mask=after_mask)
            origin = torch.tensor([0, 1, 2, 3])
            stays = torch.tensor([True, True, trial != 4, True])
            own = torch.where(torch.rand(h_in, w_in, generator=g) > 0.7, 5, 0)
            raster = torch.where(torch.rand(h_in, w_in, generator=g) > 0.5, ids[torch.randint(0, 4, (h_in, w_in),
                                                                                             generator=g)], 0)
            vis = upsample_ids(torch.where(after_mask[0], 3, 0), frame)
            for extra in ({}, {"raster_ids": raster}, {"raster_ids": raster, "vis_ids": vis, "min_seen": 3}):
                got = _grow(own.clone(), before, after, origin, stays, frame, **extra)
                want = _grow_as_it_was(own.clone(), before, after, origin, stays, frame, **extra)
                assert torch.equal(got[0], want[0]) and got[1] == want[1], (frame.input_size, trial, extra.keys())
            labels = torch.where(after_mask[0] & ~before.mask[0], 7, 0)
            box = (0, 0, 0, 0)
            if bool(labels.any()):
                ys, xs = labels.nonzero(as_tuple=True)
                box = (int(xs.min()), int(ys.min()), int(xs.max()) + 1, int(ys.max()) + 1)
            window = input_window(frame, box)
            whole = upsample_ids(labels, frame)
            if window is None:
                assert not bool(whole.any())
                continue
            x0, y0, x1, y1 = window
            assert torch.equal(upsample_ids(labels, frame, window), whole[y0:y1, x0:x1])
            inside = torch.zeros_like(whole, dtype=torch.bool)
            inside[y0:y1, x0:x1] = True
            assert not bool(whole[~inside].any())
            ones = upsample_ids(torch.ones(h, w, dtype=torch.long), frame, window)  # a pixel of the box on each edge
            boxed = torch.zeros(h, w, dtype=torch.long)
            boxed[box[1]:box[3], box[0]:box[2]] = 1
            edge = upsample_ids(boxed, frame, window) & ones
            assert bool(edge[0].any() and edge[-1].any() and edge[:, 0].any() and edge[:, -1].any())


def test_photo_path_on_cropped_fragments_draws_what_the_whole_images_drew(monkeypatch):
    """render_photo rasterizes the objects in their box (rasterize_meshes(crop=True)); with the whole image's
    fragments (crop=False) every lookup, outline, part and normal map is the same, so the pictures are."""
    from sdn3d.editing.apply import Delete
    from sdn3d.editing.photo import transfer
    from sdn3d.editing.photo.settings import PhotoSettings
    from sdn3d.render.maps import normal_map
    from sdn3d.render.rasterize import rasterize_meshes
    from tests.test_photo import _k_input

    scene = _scene([CAR, FAR_CAR])
    near, far = ((scene.objects.instance_id == i).nonzero().item() for i in (12001, 12002))
    scene.objects.mask[far] = dilate_square(scene.objects.mask[far], 2) & ~scene.objects.mask[near]  # past its outline
    scene.objects.mask[near, :, 50] = False  # a post in front of the near car that its mask leaves out
    rows, verts, faces = transfer.posed_meshes(scene.objects, transfer.default_bank())
    frags = rasterize_meshes(verts.double(), faces, _k_input(), transfer.RasterSettings(image_size=INPUT_SIZE[::-1]),
                             mesh_to_image=torch.zeros(len(rows), dtype=torch.long), batch_size=1)
    normals = normal_map(frags, verts.double(), faces)[0]
    light = F.normalize(torch.tensor([-0.6, -0.6, -0.5], dtype=torch.float64), dim=0)
    shade = 0.3 + 0.7 * (normals * light[:, None, None]).sum(0)
    g = torch.Generator().manual_seed(8)
    image = (0.45 + 0.05 * torch.rand(3, INPUT_SIZE[1], INPUT_SIZE[0], generator=g)).double()
    image = torch.where(frags.mask[0][None], 0.8 * shade.clamp(min=0)[None], image)
    image[:, :, 100:102] = 0.05  # the post
    original = (image.clamp(0, 1) * 255).round().to(torch.uint8)
    edits = ([Move(12001, (40.0, 42.0)), Rotate(12001, math.radians(70))], [Rotate(12002, math.radians(-120))],
             [Delete(12001)], [Move(12002, (95.0, 40.0))])
    settings = (PhotoSettings(relight=True), PhotoSettings(fill="telea", unseen="body"))

    def draw():
        return [render_photo(original, FRAME, scene, apply_edits(scene, ops), settings=s) for ops in edits
                for s in settings]

    cropped = draw()
    monkeypatch.setattr(transfer, "rasterize_meshes", lambda *a, **k: rasterize_meshes(*a, **{**k, "crop": False}))
    whole = draw()
    for got, want in zip(cropped, whole, strict=True):
        assert torch.equal(got.image, want.image) and torch.equal(got.source, want.source)
        assert torch.equal(got.parts, want.parts) and got.objects == want.objects
    assert any(bool((r.source == transfer.PHOTO).any()) for r in whole)
    assert sum(r.light is not None for r in whole) >= 2
    assert bool((whole[0].source == transfer.IN_FRONT).any())


def test_part_examples_summing_by_sum3_are_those_of_torchs_sum(monkeypatch):
    """``_part_examples`` (its surface points and, through ``_view_cos``, their view cosines summed over three by
    :func:`~sdn3d.math3d.sums.sum3`) keeps the very examples, colours, features and cosines it kept with torch's
    ``sum``: a textured car seen from the rear three-quarter, every visible pixel offered."""
    from sdn3d.editing.photo import transfer
    from sdn3d.editing.photo.transfer import _part_examples, _surface, _view_cos
    from sdn3d.scene.code import SceneObject
    from tests.test_photo_parts import PARTS

    car = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=-math.pi / 2 + 0.7, location=(-1.0, 1.6, 9.0))
    scene = _scene([car])
    image = torch.rand((3, *INPUT_SIZE[::-1]), generator=torch.Generator().manual_seed(4))
    src = PhotoSource(image, FRAME, scene, settings=PARTS)
    visible = (src.vis_ids.view(-1) == 12001).nonzero().flatten()
    img_flat = image.permute(1, 2, 0).reshape(-1, 3)
    _, vid, bary, normal = _surface(src.raster, visible)
    point = (bary[..., None] * src.raster.verts[0, vid]).sum(1)
    point[:5] = 0.0  # a point at the camera: normalize gives zeros
    got = [_view_cos(point, normal), *_part_examples(0, 0, visible, scene.objects, src.raster, src.parts, img_flat,
                                                      None, PARTS)]
    monkeypatch.setattr(transfer, "sum3", lambda x, dim=-1, keepdim=False: x.sum(dim, keepdim=keepdim))
    want = [_view_cos(point, normal), *_part_examples(0, 0, visible, scene.objects, src.raster, src.parts, img_flat,
                                                       None, PARTS)]
    assert len(got[1].part) > 100 and torch.equal(got[0], want[0]) and torch.equal(got[2], want[2])
    assert torch.equal(got[0], (F.normalize(point, dim=-1) * normal).sum(-1).abs())  # _view_cos as it was
    assert all(torch.equal(a, b) and a.dtype == b.dtype for a, b in zip(got[1], want[1], strict=True))


def test_linear_rgb_of_8bit_levels_by_lut_is_numpys_take():
    """``_linear_of_levels`` (OpenCV's ``LUT``) gives ``np.take(_LINEAR_LEVELS, levels)`` bit for bit in every layout
    :class:`PictureLab` hands it: a box's rows (contiguous, or a strided view of whole rows), a boolean selection,
    one pixel, no pixels."""
    import numpy as np

    from sdn3d.editing.photo.road import _LINEAR_LEVELS, _linear_of_levels

    levels = torch.randint(256, (3, 40, 70), dtype=torch.uint8, generator=torch.Generator().manual_seed(6)).numpy()
    levels[:, :4, :64] = np.arange(256, dtype=np.uint8).reshape(4, 64)  # every level
    selected = levels[:, levels[0] > 100]
    for values in (levels.reshape(3, -1), levels[:, 3:9].reshape(3, -1), levels[:, 3:9, 5:40].reshape(3, -1),
                   selected, selected[:, :1], selected[:, :0]):
        got, want = _linear_of_levels(values), np.take(_LINEAR_LEVELS, values)
        assert got.dtype == want.dtype == np.float32 and got.shape == want.shape
        assert np.array_equal(got.view(np.uint32), want.view(np.uint32)) and got.flags.c_contiguous


def test_mask_tests_by_numpy_are_torchs_any_and_nonzero():
    """:func:`~sdn3d.image_ops.any_set`, :func:`~sdn3d.image_ops.any_along`, :func:`~sdn3d.image_ops.count_set`,
    :func:`~sdn3d.image_ops.flat_nonzero` and :func:`~sdn3d.image_ops.nonzero_yx` (NumPy on a bool CPU mask) are
    torch's ``any``, ``any(dim)``, ``int(sum())``, ``reshape(-1).nonzero().flatten()`` and ``nonzero(as_tuple=True)``,
    values, dtypes and layouts: masks empty,
    full, with one pixel set (at a corner and inside), sliced, transposed and 3-D, along each dimension; a float
    tensor (torch's own, NaN counting as set) and a 0-d mask."""
    from sdn3d.image_ops import any_along, any_set, count_set, flat_nonzero, nonzero_yx

    gen = torch.Generator().manual_seed(7)
    one = torch.zeros(37, 53, dtype=torch.bool)
    one[36, 52] = True
    inside = torch.zeros(37, 53, dtype=torch.bool)
    inside[20, 7] = True
    sparse = torch.rand(37, 53, generator=gen) > 0.995
    masks = [torch.zeros(37, 53, dtype=torch.bool), torch.ones(37, 53, dtype=torch.bool), one, inside, sparse,
             sparse[5:30, 9:40], sparse.T, one[:-1, :-1], inside[::2, 3::5], torch.zeros(0, 53, dtype=torch.bool),
             torch.rand(3, 20, 30, generator=gen) > 0.99, torch.tensor(True), torch.tensor(False),
             torch.tensor([[0.0, float("nan")], [-0.0, 0.0]]), torch.tensor([[0.0, -0.0], [0.0, 0.0]])]
    for mask in masks:
        assert any_set(mask) is bool(mask.any())
        if mask.dtype == torch.bool:
            assert count_set(mask) == int(mask.sum()) and isinstance(count_set(mask), int)
        for dim in range(-mask.dim(), mask.dim()):
            got, want = any_along(mask, dim), mask.any(dim)
            assert torch.equal(got, want) and got.dtype == want.dtype == torch.bool
        got, want = flat_nonzero(mask), mask.reshape(-1).nonzero().flatten()
        assert torch.equal(got, want) and got.dtype == want.dtype and got.stride() == want.stride()
        if mask.dim() == 2:
            for got, want in zip(nonzero_yx(mask), mask.nonzero(as_tuple=True), strict=True):
                assert torch.equal(got, want) and got.dtype == want.dtype and got.is_contiguous()
    with pytest.raises(ValueError, match="2-D"):
        nonzero_yx(masks[10])


def test_mask_centroids_by_counts_are_the_grid_weighted_means_bit_for_bit():
    """:func:`~sdn3d.image_ops.mask_centroids` (per-column and per-row counts, NumPy on a bool CPU mask) is the
    picking rule's former centroid, the masks weighed by a float64 coordinate grid, bit for bit: masks empty, full,
    one pixel at a corner, sparse, sliced and transposed; a float mask (torch's path); a 2-D mask is refused."""
    from sdn3d.image_ops import mask_centroids

    def grid_weighted(masks: torch.Tensor) -> torch.Tensor:
        h, w = masks.shape[-2:]
        grid = torch.stack(torch.meshgrid(torch.arange(h, dtype=torch.float64), torch.arange(w, dtype=torch.float64),
                                          indexing="ij"), -1)  # (H, W, [v, u])
        area = masks.flatten(1).sum(1).double()
        return torch.einsum("nhw,hwc->nc", masks.double(), grid).flip(-1) / area.clamp(min=1)[:, None]

    gen = torch.Generator().manual_seed(9)
    sparse = torch.rand(5, 61, 97, generator=gen) > 0.7
    sparse[0] = False
    sparse[1] = True
    sparse[2] = False
    sparse[2, 60, 96] = True
    for masks in (sparse, sparse[:, 7:50, 3:80], sparse.transpose(1, 2), sparse[:0]):
        got = mask_centroids(masks)
        assert got.dtype == torch.float64 and torch.equal(got, grid_weighted(masks))
    assert torch.equal(mask_centroids(sparse.float()), grid_weighted(sparse))
    assert mask_centroids(sparse)[0].tolist() == [0.0, 0.0] and mask_centroids(sparse)[2].tolist() == [96.0, 60.0]
    with pytest.raises(ValueError, match="N, H, W"):
        mask_centroids(sparse[0])


def test_channel_mean_by_sum3_is_torchs_mean():
    """``ray_fill``'s grain level: the channels' mean as ``sum3(x, 0) / 3`` is torch's ``x.mean(0)`` bit for bit on
    a ``(3, H, W)`` float32 picture in channel-last memory (as decoded pictures arrive) and contiguous, with -0.0,
    infinities, NaN and values from 1e-30 to 1e30; the same layout out."""
    from sdn3d.math3d.sums import sum3

    gen = torch.Generator().manual_seed(8)
    channel_last = torch.randn(40, 70, 3, generator=gen).permute(2, 0, 1) * torch.logspace(-30, 30, 70)
    channel_last[:, :3] = -0.0
    channel_last[0, 5, :9] = float("inf")
    channel_last[1, 6, 3:12] = float("-inf")
    channel_last[2, 7, 4] = float("nan")
    for x in (channel_last, channel_last.contiguous(), channel_last * (torch.rand(40, 70, generator=gen) > 0.3)):
        got, want = sum3(x, 0) / 3, x.mean(0)
        same = (got.view(torch.int32) == want.view(torch.int32)) | (got.isnan() & want.isnan())
        assert bool(same.all()) and got.stride() == want.stride()


def _sample_every_level(pyramid, uv, level):
    """``_sample`` as it was: every level of the pyramid sampled at every point, two of them blended per point."""
    height, width = pyramid[0].shape[-2:]
    grid = torch.stack([(uv[:, 0] + 0.5) / width * 2 - 1, (uv[:, 1] + 0.5) / height * 2 - 1], 1)
    grid = grid.float()[None, None]
    samples = torch.stack([F.grid_sample(p, grid, mode="bilinear", padding_mode="border",
                                         align_corners=False)[0, :, 0].T for p in pyramid])
    level = level.clamp(0, len(pyramid) - 1).float()
    lo = level.floor().long()
    hi = (lo + 1).clamp(max=len(pyramid) - 1)
    t = (level - lo.float())[:, None]
    idx = torch.arange(len(uv))
    return samples[lo, idx] * (1 - t) + samples[hi, idx] * t


def test_sample_of_the_levels_blended_is_every_levels_sample():
    """``_sample`` samples the pyramid's levels down to the deepest one some point blends; the values are those of
    sampling every level: points off the picture, levels 0 everywhere (a turn), mixed, past the deepest level and below
    0, one level, none."""
    from sdn3d.editing.photo.transfer import _sample

    g = torch.Generator().manual_seed(5)
    image = torch.rand(3, 75, 124, generator=g)
    pyramid = _pyramid(image, 3)
    uv = torch.rand(500, 2, generator=g, dtype=torch.float64) * torch.tensor([140.0, 90.0]) - 8.0
    levels = [torch.zeros(500, dtype=torch.float64), torch.rand(500, generator=g, dtype=torch.float64) * 3.5,
              torch.full((500,), 1.0, dtype=torch.float64), torch.rand(500, generator=g, dtype=torch.float64) * 9 - 2,
              torch.tensor([2.5] * 499 + [0.0], dtype=torch.float64)]
    for level in levels:
        for pyr in (pyramid, pyramid[:1], pyramid[:2]):
            got, want = _sample(pyr, uv, level), _sample_every_level(pyr, uv, level)
            assert torch.equal(got, want) and got.dtype == want.dtype
    empty = _sample(pyramid, uv[:0], levels[0][:0])
    assert empty.shape == (0, 3) and empty.dtype == torch.float32


def test_draw_reads_the_air_of_cars_it_takes_no_examples_from_without_their_examples(monkeypatch):
    """``_draw`` asks whether each car it passes over for another car's wheel is seen through clear air (``_clear_air``
    of its visible colours) without making that car's part examples; those colours are the ones ``_part_examples``
    returns, so the picture is the same. A car seen from behind turned 90 degrees looks at every other car for a
    real wheel (none is dark); the far car, which grows into the freed pixels, takes tyres from the cars nearest
    it in depth; the near car on the right is looked at for its wheel and for the head lamps the turned car's
    never-seen front may take from another car (``LAMPS_FROM_ANOTHER_CAR``: none shows any, so every car's examples
    are made; main made none of the right car's)."""
    from sdn3d.editing.photo import transfer
    from sdn3d.scene.code import SceneObject
    from tests.test_photo_parts import BEHIND, PARTS, _painted

    side = SceneObject(12002, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.0, location=(3.0, 1.6, 14.0))
    far = SceneObject(12003, template_id=1, dims=(4.2, 1.6, 1.9), ry=0.3, location=(-3.0, 1.6, 24.0))
    right = SceneObject(12004, template_id=2, dims=(4.0, 1.5, 1.8), ry=0.5, location=(4.5, 1.6, 9.0))
    scene = _scene([BEHIND, side, far, right])
    image, covered, parts = _painted(scene, (0.6, 0.6, 0.6))
    image[:, covered & (parts == int(transfer.Part.GLASS))] = 0.05  # dark windows: every car seen through clear air
    edited = apply_edits(scene, [Rotate(12001, math.pi / 2)])
    made, air = [], []
    part_examples, clear_air = transfer._part_examples, transfer._clear_air
    monkeypatch.setattr(transfer, "_part_examples", lambda b, *a: made.append((b, part_examples(b, *a))) or made[-1][1])
    monkeypatch.setattr(transfer, "_clear_air", lambda colors, *a: air.append(colors) or clear_air(colors, *a))
    render_photo(image, FRAME, scene, edited, settings=PARTS)
    assert [int(scene.objects.instance_id[b]) for b, _ in made] == [12001, 12002, 12004, 12003]
    src = PhotoSource(image, FRAME, scene, settings=PARTS)
    img_flat = image.permute(1, 2, 0).reshape(-1, 3)
    seen = [img_flat[(src.vis_ids.view(-1) == i).nonzero().flatten()].double() for i in scene.objects.instance_id]
    assert len(air) == 4 and all(sum(torch.equal(a, s) for a in air) == 1 for s in seen)  # each car's air, once
    for b, (_, colors) in made:
        assert torch.equal(colors, seen[b])  # what _part_examples returns: the colours the air is read from


def test_a_source_makes_each_cars_part_examples_and_reads_its_air_once_for_all_its_edits(monkeypatch):
    """A kept source state makes each car's part examples and reads each car's air (``_clear_air``) once for all the
    edits drawn from it (they depend on the input alone): turning the car seen from behind by 90, then 180, then 90
    degrees again, as an editor's drag does, makes them on the first turn only, and each picture equals the one a
    fresh source state draws (main made them again on every turn)."""
    from sdn3d.editing.photo import transfer
    from sdn3d.scene.code import SceneObject
    from tests.test_photo_parts import BEHIND, PARTS, _painted

    side = SceneObject(12002, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.0, location=(3.0, 1.6, 14.0))
    far = SceneObject(12003, template_id=1, dims=(4.2, 1.6, 1.9), ry=0.3, location=(-3.0, 1.6, 24.0))
    scene = _scene([BEHIND, side, far])
    image, covered, parts = _painted(scene, (0.6, 0.6, 0.6))
    image[:, covered & (parts == int(transfer.Part.GLASS))] = 0.05  # dark windows: every car seen through clear air
    made, air = [], []
    part_examples, clear_air = transfer._part_examples, transfer._clear_air
    monkeypatch.setattr(transfer, "_part_examples", lambda b, *a: made.append(b) or part_examples(b, *a))
    monkeypatch.setattr(transfer, "_clear_air", lambda colors, *a: air.append(len(colors)) or clear_air(colors, *a))
    source = PhotoSource(image, FRAME, scene, settings=PARTS)
    turns = [apply_edits(scene, [Rotate(12001, math.radians(deg))]) for deg in (90, 180, 90)]
    kept = [render_photo(image, FRAME, scene, edited, settings=PARTS, source=source) for edited in turns]
    assert made and sorted(made) == sorted(set(made))  # each car's examples made once, on the first turn
    assert len(air) == len(set(made)) == 3  # the turned car's and the two cars its tyres are looked for on
    for edited, picture in zip(turns, kept, strict=True):
        fresh = render_photo(image, FRAME, scene, edited, settings=PARTS)
        assert torch.equal(picture.image, fresh.image) and torch.equal(picture.source, fresh.source)
        assert torch.equal(picture.parts, fresh.parts)
    assert len(made) == 4 * 3  # a fresh state makes its own


def test_nearest_examples_pytorch_path_in_blocks_is_one_calls_bit_for_bit(monkeypatch):
    """Without the kernel, ``nearest_examples`` looks at a few hundred query rows at a time (``NEAREST_ROWS``: their
    distances stay in cache between ``cdist`` and ``topk``), and its indices are those of one ``cdist`` + ``topk`` on
    every row, the formulation it replaced (8192 rows at a time), bit for bit: fewer and more rows than a block,
    blocks whose last one is small, few examples (``cdist``'s other formula below 26 rows on both sides), near ties
    and exact ties (repeated examples). Main looked at 8192 rows at a time."""
    from sdn3d.editing.photo import nearest

    monkeypatch.setattr(nearest, "nearest_kernel", lambda: None)

    def one_call(query, examples, k):
        k = min(k, len(examples))
        query, examples = query.float(), examples.float()
        return torch.cat([torch.cdist(c, examples).topk(k, largest=False).indices for c in query.split(8192)])

    g = torch.Generator().manual_seed(3)
    rows = []
    cdist = torch.cdist
    monkeypatch.setattr(torch, "cdist", lambda a, b, **kw: rows.append(len(a)) or cdist(a, b, **kw))
    for q, e, k in ((3000, 1500, 4), (1030, 700, 16), (530, 20, 4), (20, 20, 4), (513, 12, 4), (9000, 40, 4),
                    (0, 30, 4), (30, 3, 4)):
        examples = torch.rand(e, 6, generator=g, dtype=torch.float64)
        examples[e // 2:] = examples[:e - e // 2].clone()  # every example twice: exact ties
        query = torch.rand(q, 6, generator=g, dtype=torch.float64)
        query[::7] = examples[torch.arange(0, q, 7) % e] + 1e-7  # near ties
        got = nearest.nearest_examples(query, examples, k)
        with monkeypatch.context() as m:
            m.setattr(torch, "cdist", cdist)
            want = one_call(query, examples, k)
        assert torch.equal(got, want), (q, e, k)
    assert max(rows) < 8192  # the 9000 queries: main took 8192 rows at once
    assert max(rows) <= nearest.NEAREST_ROWS


def test_the_roads_medians_select_as_a_boolean_index_would():
    # _road_of's medians of channel-major Lab rows (NumPy's compress and partition) against _column_median of the
    # rows selected by torch, on both sides of MEDIAN_NUMPY_MIN and with many ties (8-bit levels)
    g = torch.Generator().manual_seed(11)
    for n in (40, 5000, 30000):
        rgb = (torch.randint(0, 256, (3, n), generator=g).float() / 255)
        lab = road_lab(rgb.T.contiguous())  # (n, 3), channel-major
        rows = torch.rand(n, generator=g) < 0.6
        assert torch.equal(photo_road._selected_median(lab, rows), photo_road._column_median(lab[rows]))
        assert torch.equal(photo_road._selected_median(lab[:, 1:], rows), photo_road._column_median(lab[rows][:, 1:]))
        flat = lab.contiguous()  # row-major: torch's path
        assert torch.equal(photo_road._selected_median(flat, rows), photo_road._column_median(flat[rows]))


def test_the_rings_lab_is_road_lab_of_the_selected_pixels():
    g = torch.Generator().manual_seed(12)
    image = torch.rand(3, 60, 90, generator=g)
    ring = torch.rand(60, 90, generator=g) < 0.3
    want = road_lab(image[:, ring].T.contiguous())
    assert torch.equal(photo_road._ring_lab(image, ring, None), want)
    thinned = image[:, :, ::3]  # road_haze's every third column: a strided picture
    want = road_lab(thinned[:, ring[:, ::3]].T.contiguous())
    assert torch.equal(photo_road._ring_lab(thinned, ring[:, ::3], None), want)
