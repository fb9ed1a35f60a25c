"""What a delete leaves to the fill (session 4, issue 41 item 3): amodal completion only of cars the input showed,
never where a car's own fitted outline claims to be in front of the removed car; and the rays' grain matched to the
road around the hole (``ray_grain='match'``), without the ghost outlines of markings."""

from __future__ import annotations

import pytest
import torch

from sdn3d.editing.apply import Delete, apply_edits
from sdn3d.editing.frame import upsample_ids
from sdn3d.editing.photo.road import ray_fill
from sdn3d.editing.photo.settings import FILL, INPUT, PhotoSettings, PhotoSettingsError
from sdn3d.editing.photo.transfer import render_photo
from sdn3d.scene.code import SceneObject

pytestmark = pytest.mark.usefixtures("one_torch_thread")

NEAR = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.0, location=(0.0, 1.6, 8.0))
HIDDEN = SceneObject(12002, template_id=0, dims=(4.0, 1.2, 1.6), ry=0.0, location=(0.0, 1.6, 20.0))
SIDE = SceneObject(12002, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.0, location=(2.5, 1.6, 16.0))
#: amodal='all': the freed pixels' rules of these tests alone (amodal='seen' would also leave their flat pixels).
SETTINGS = PhotoSettings(relight=False, contact_shadow=0.0, fill="telea", amodal="all")


def _drawn(result) -> torch.Tensor:
    """Pixels an object was drawn on (neither the input's nor the fill's)."""
    return (result.source != INPUT) & (result.source != FILL)


def test_a_car_the_input_never_showed_is_left_to_the_fill():
    from tests.test_photo import FRAME, _k_input, _scene, _surface_colors

    scene = _scene([NEAR, HIDDEN])
    assert int(scene.objects.mask[1].sum()) <= 2  # behind the near car: a pixel of its roof, none after erosion
    image, _ = _surface_colors(scene, FRAME.input_size[::-1], _k_input())
    edited = apply_edits(scene, [Delete(12001)])
    assert int(edited.objects.mask[0].sum()) > 0  # amodal completion gave it the freed pixels
    before = render_photo(image, FRAME, scene, edited, settings=PhotoSettings(**{**SETTINGS.to_dict(),
                                                                                 "grow_min_seen": 0}))
    assert int(_drawn(before).sum()) > 100  # drawn in guessed colours, the behaviour before
    now = render_photo(image, FRAME, scene, edited, settings=SETTINGS)
    assert int(_drawn(now).sum()) == 0 and 12002 not in now.objects


def test_a_nearer_cars_outline_does_not_grow_into_the_removed_car_behind_it():
    """The near car's mask is its silhouette less a 2-pixel rim on the side of the far car (its true outline smaller
    than its fitted shape), and that rim showed the far car; deleting the far car must not hand the rim to the near
    car, whose fitted shape claims to be in front there."""
    from tests.test_photo import FRAME, _k_input, _scene, _surface_colors

    scene = _scene([NEAR, SIDE])
    masks = scene.objects.mask.clone()
    near = masks[0]
    grown_far = torch.nn.functional.max_pool2d(masks[1][None, None].float(), 5, 1, 2)[0, 0] > 0
    rim = near & grown_far
    assert int(rim.sum()) > 5
    masks[0] = near & ~rim
    masks[1] = masks[1] | rim
    scene = scene.replace(objects=scene.objects.replace(mask=masks))
    image, _ = _surface_colors(scene, FRAME.input_size[::-1], _k_input())
    edited = apply_edits(scene, [Delete(12002)])
    assert bool((edited.objects.mask[0] & rim).any())  # apply_edits' amodal completion hands the rim back
    rim_in = upsample_ids(rim.long(), FRAME).bool()
    old = render_photo(image, FRAME, scene, edited, settings=PhotoSettings(**{**SETTINGS.to_dict(),
                                                                              "grow_min_seen": 0}))
    assert int(_drawn(old)[rim_in].sum()) > 10
    now = render_photo(image, FRAME, scene, edited, settings=SETTINGS)
    assert int(_drawn(now)[rim_in].sum()) == 0 and bool((now.source[rim_in] == FILL).all())


def _road(grain: float, seed: int = 0) -> tuple[torch.Tensor, torch.Tensor]:
    """``(image, hole)``: grey road below row 22 with a converging white line, grain of std ``grain``, sky above;
    a hole on the road."""
    from tests.test_photo_road import _lanes

    gen = torch.Generator().manual_seed(seed)
    image, _ = _lanes()
    image = (image + grain * torch.randn(image.shape, generator=gen)).clamp(0, 1)
    hole = torch.zeros(image.shape[1:], dtype=torch.bool)
    hole[38:58, 20:60] = True
    return image, hole


def _texture(image: torch.Tensor, mask: torch.Tensor) -> float:
    """Mean absolute 3x3 Laplacian of the mean channel over ``mask``, away from the picture's edge."""
    g = image.mean(0)
    lap = (4 * g[1:-1, 1:-1] - g[:-2, 1:-1] - g[2:, 1:-1] - g[1:-1, :-2] - g[1:-1, 2:]).abs()
    return float(lap[mask[1:-1, 1:-1]].mean())


def test_matched_grain_follows_the_roads_own_grain():
    inner = torch.zeros(64, 128, dtype=torch.bool)
    inner[40:56, 22:58] = True
    ring = torch.zeros_like(inner)
    ring[30:64, 5:90] = True
    ring[28:66, 12:68] = False
    levels = []
    for grain in (0.01, 0.06):
        image, hole = _road(grain)
        filled, _ = ray_fill(image, hole, (63.5, 20.0), texture=0.25, match_grain=True)
        fixed, _ = ray_fill(image, hole, (63.5, 20.0), texture=0.25)
        levels.append((_texture(filled, inner), _texture(fixed, inner), _texture(image, ring)))
    (fine_m, fine_f, fine_r), (coarse_m, coarse_f, coarse_r) = levels
    # a fixed weight leaves a grainy road smoother than around it; matched, the fill is as grainy as the road
    assert coarse_f < 0.8 * coarse_r
    assert 0.8 * coarse_r < coarse_m < 1.25 * coarse_r
    assert coarse_m > 2 * fine_m  # and a smooth road's fill stays smooth


def test_a_markings_outline_is_not_mirrored_into_the_hole_as_grain(monkeypatch):
    """Rays along the rows (the vanishing point far to the right); a white dash 7 pixels left of the hole. The grain
    mirrored across the hole's left edge reads the dash's outline: without the edge cut it draws ghost columns."""
    import sdn3d.editing.photo.road as road

    gen = torch.Generator().manual_seed(0)
    image = (0.4 + 0.01 * torch.randn(3, 64, 128, generator=gen)).clamp(0, 1)
    image[:, 40:56, 30:33] = 0.95
    hole = torch.zeros(64, 128, dtype=torch.bool)
    hole[40:56, 40:80] = True
    filled, _ = ray_fill(image, hole, (1000.0, 48.0), texture=1.0)
    assert float((filled[:, hole] - 0.4).abs().max()) < 0.06  # grain only
    monkeypatch.setattr(road, "GRAIN_EDGE", float("inf"))
    ghost, _ = ray_fill(image, hole, (1000.0, 48.0), texture=1.0)
    assert float((ghost[:, hole] - 0.4).abs().max()) > 0.15  # the dash's outline, mirrored


def test_new_delete_settings_are_checked():
    assert PhotoSettings().ray_grain == "match" and PhotoSettings().grow_min_seen == 1
    with pytest.raises(PhotoSettingsError, match="ray_grain"):
        PhotoSettings(ray_grain="strong")
    with pytest.raises(PhotoSettingsError, match="grow_min_seen"):
        PhotoSettings(grow_min_seen=-1)


#: A 624x192 camera (the synthetic benchmark's size) for the vanishing point's votes.
ROAD_K = torch.tensor([[364.0, 0.0, 311.5], [0.0, 364.0, 95.5], [0.0, 0.0, 1.0]])


def _perspective_road(heading_deg: float, grass: float = 0.0) -> torch.Tensor:
    """``(3, 192, 624)``: a level camera 1.6 m above a grey road whose three lane lines (0.15 m wide, 1.8 m apart)
    run ``heading_deg`` degrees right of its forward direction, antialiased (3x3 samples a pixel), sky above the
    horizon; with ``grass`` > 0, right of the road (beyond 2.2 m) a verge of fine, high-contrast grass (smoothed noise
    of that standard deviation)."""
    import math

    import torch.nn.functional as F

    fx, cx, cy, ss = float(ROAD_K[0, 0]), float(ROAD_K[0, 2]), float(ROAD_K[1, 2]), 3
    ys, xs = torch.meshgrid((torch.arange(192 * ss) + 0.5) / ss - 0.5, (torch.arange(624 * ss) + 0.5) / ss - 0.5,
                            indexing="ij")
    below = ys > cy + 0.5
    z = fx * 1.6 / (ys - cy).clamp(min=1e-3)  # the road point's depth
    across = (xs - cx) * z / fx * math.cos(math.radians(heading_deg)) - z * math.sin(math.radians(heading_deg))
    lines = below & torch.stack([(across - o).abs() < 0.075 for o in (-1.8, 0.0, 1.8)]).any(0)
    road = torch.where(lines, 0.92, 0.42)
    image = torch.stack([road, road, road * 1.03])
    image[:, ~below] = torch.tensor([0.6, 0.75, 0.9])[:, None]
    image = F.avg_pool2d(image[None], ss)[0]
    if grass > 0:
        noise = torch.rand(1, 1, 192, 624, generator=torch.Generator().manual_seed(0))
        k = torch.exp(-0.5 * (torch.arange(-4, 5.0) / 1.2) ** 2)
        k = k / k.sum()
        noise = F.conv2d(noise, k.view(1, 1, 1, -1), padding=(0, 4))
        noise = F.conv2d(noise, k.view(1, 1, -1, 1), padding=(4, 0))[0, 0]
        noise = (noise - noise.mean()) / noise.std()
        verge = F.avg_pool2d((below & (across > 2.2)).float()[None, None], ss)[0, 0] > 0.5
        for c, base, amp in ((0, 0.55, grass), (1, 0.65, grass), (2, 0.25, grass / 2)):
            image[c][verge] = base + amp * noise[verge]
    return image.clamp(0, 1)


def _heading(u: float) -> float:
    import math

    return math.degrees(math.atan((u - float(ROAD_K[0, 2])) / float(ROAD_K[0, 0])))


def test_the_voted_vanishing_point_snaps_to_the_cameras_forward_heading_only_within_a_degree():
    from sdn3d.road_heading import FORWARD_SNAP_DEG, image_vanishing_point

    region = torch.ones(192, 624, dtype=torch.bool)
    slight = _perspective_road(0.5)  # lanes half a degree off the forward heading
    assert _heading(image_vanishing_point(slight, region, ROAD_K)[0]) == pytest.approx(0.5, abs=0.01)  # the vote
    u_snap, v = image_vanishing_point(slight, region, ROAD_K, forward_snap_deg=FORWARD_SNAP_DEG)
    assert u_snap == pytest.approx(311.5) and v == pytest.approx(95.5)  # within a degree: the camera's forward
    for heading in (2.0, -30.0, 30.0):  # a road turned more: the real frame's camera is 30 degrees off
        u, _ = image_vanishing_point(_perspective_road(heading), region, ROAD_K, forward_snap_deg=FORWARD_SNAP_DEG)
        assert _heading(u) == pytest.approx(heading, abs=0.01)


def test_a_grassy_verges_texture_does_not_outvote_the_lane_lines():
    """The real frame's failure: the road runs 30 degrees left of the camera's forward heading and a verge of fine,
    high-contrast grass fills the picture's right part below the horizon. Its strong gradients point every way;
    counted as edges (coherence 0) they take the vote far off the road; only the lines' coherence keeps it."""
    from sdn3d.road_heading import FORWARD_SNAP_DEG, image_vanishing_point

    image = _perspective_road(-30.0, grass=0.3)
    region = torch.ones(192, 624, dtype=torch.bool)
    u, _ = image_vanishing_point(image, region, ROAD_K, forward_snap_deg=FORWARD_SNAP_DEG)
    assert _heading(u) == pytest.approx(-30.0, abs=0.01)
    fooled, _ = image_vanishing_point(image, region, ROAD_K, coherence=0.0, forward_snap_deg=FORWARD_SNAP_DEG)
    assert abs(_heading(fooled) + 30.0) > 10.0


# -- session 5: one-sided markings, shadowed road above the ground ---------------------------------------------------


def test_a_dash_seen_on_one_side_of_the_hole_is_not_drawn_out_into_a_stripe():
    """The middle lane line is a dash below the hole only; without ``marks`` the rays interpolate it towards the
    plain road above into a fading stripe, with ``marks`` they take the road; a solid line still crosses."""
    from tests.test_photo_road import _lanes

    image, line = _lanes()
    middle = line & (torch.arange(128)[None, :] - 63.5).abs().lt(6)
    dash = image.clone()
    dash[:, middle & (torch.arange(64)[:, None] < 52)] = dash[:, 60, 20][:, None]  # the line only below row 52
    hole = torch.zeros_like(line)
    hole[34:52, 40:90] = True
    on = hole & middle
    stripe, _ = ray_fill(dash, hole, (63.5, 20.0), texture=0.0)
    assert float(stripe[:, on].mean()) > 0.55  # the dash drawn out into the hole (the behaviour before)
    road, _ = ray_fill(dash, hole, (63.5, 20.0), texture=0.0, marks=0.15)
    assert float(road[:, on].mean()) < 0.45
    solid, _ = ray_fill(image, hole, (63.5, 20.0), texture=0.0, marks=0.15)
    assert float(solid[:, hole & line].mean()) > 0.8


def test_shadowed_road_above_the_ground_rows_is_a_source_of_the_rays(monkeypatch):
    """Road-coloured pixels darker than the lit road above the hole (a shaded far road) are what the hole's upper
    part shows; only the ground rows (``SHADOW_GROUND`` of the hole's height down) keep shadowed road out."""
    import sdn3d.editing.photo.transfer as transfer
    from sdn3d.editing.photo.road import road_colours

    height, width = 64, 128
    image = torch.full((3, height, width), 0.5)
    image[:, :20, 52:76] = 0.3  # shaded road above the hole (lit road on its rows either side)
    hole = torch.zeros(height, width, dtype=torch.bool)
    hole[20:40, 40:88] = True
    search = torch.zeros_like(hole)
    search[34:40, 40:88] = True  # the removed car's footprint: its shadow's place
    ring = ~hole & ~torch.nn.functional.max_pool2d(hole.float()[None, None], 13, 1, 6)[0, 0].bool()
    road = road_colours(image, ring)
    settings = PhotoSettings(fill="rays", ray_grain="fixed", ray_texture=0.0)
    objects = torch.zeros_like(hole)
    filled, _ = transfer._rays_with_effects(image, hole, objects, search, ring, road, settings, (64.0, -2000.0))
    top = (slice(None), slice(20, 24), slice(56, 72))
    assert float(filled[top].mean()) < 0.4  # continues the shaded road above it
    # every shadowed pixel kept out (the behaviour before)
    monkeypatch.setattr(transfer, "_ground_rows", lambda mask, hole, share: mask)
    before, _ = transfer._rays_with_effects(image, hole, objects, search, ring, road, settings, (64.0, -2000.0))
    assert float(before[top].mean()) > 0.45


def test_ray_marks_setting_is_checked():
    assert PhotoSettings().ray_marks == 0.2
    with pytest.raises(PhotoSettingsError, match="ray_marks"):
        PhotoSettings(ray_marks=-0.1)


# -- session 6: fog along the rays ------------------------------------------------------------------------------------


def _foggy_road(fog: float, height: int = 96, width: int = 160, horizon: float = 30.0) -> torch.Tensor:
    """Grey road below ``horizon`` whose colour goes from 0.4 near the camera to ``fog`` at the horizon as fog
    makes it (``fog + (0.4 - fog) * exp(-20 / rows below the horizon)``), sky of the fog's colour above."""
    rows = torch.arange(height, dtype=torch.float32)
    x = torch.exp(-20.0 / (rows - horizon).clamp(min=0.5))
    road = fog + (0.4 - fog) * x
    road[rows <= horizon] = fog
    return road[None, :, None].expand(3, height, width).clone()


def test_fog_along_the_rays_lightens_near_road_carried_towards_the_horizon():
    """A hole over the vanishing point in fog: its rays find near road below only, and without ``haze`` carry its
    darker colour up to the horizon; with it the fill follows the road's fitted fog profile. A clear road (no
    profile) is filled the same either way."""
    from sdn3d.editing.photo.road import road_haze

    vp = (80.0, 30.0)
    hole = torch.zeros(96, 160, dtype=torch.bool)
    hole[26:60, 65:95] = True
    foggy = _foggy_road(0.8)
    dark, _ = ray_fill(foggy, hole, vp, texture=0.0)
    fogged, _ = ray_fill(foggy, hole, vp, texture=0.0, haze=1.0)
    far = (slice(None), slice(36, 48), slice(74, 86))
    truth = float(foggy[far].mean())
    assert abs(float(dark[far].mean()) - truth) > 0.1
    assert abs(float(fogged[far].mean()) - truth) < 0.03
    from sdn3d.editing.photo.fill import fill_hole  # photo.ray_haze reaches the rays

    # the rays alone (ray_vanishing='near': none of them has a far side here, the hole covers the vanishing point)
    fixed = {"fill": "rays", "ray_grain": "fixed", "ray_texture": 0.0, "ray_vanishing": "near"}
    on = fill_hole(foggy, hole, PhotoSettings(**fixed), vanishing=vp)
    off = fill_hole(foggy, hole, PhotoSettings(**fixed, ray_haze=0.0), vanishing=vp)
    assert abs(float(on[far].mean()) - truth) < 0.03 < abs(float(off[far].mean()) - truth)
    clear = _foggy_road(0.4)
    assert road_haze(clear, ~hole, hole, vp[1]) is None or torch.allclose(
        ray_fill(clear, hole, vp, texture=0.0, haze=1.0)[0], ray_fill(clear, hole, vp, texture=0.0)[0], atol=1e-3)


def test_ray_haze_setting_is_checked():
    assert PhotoSettings().ray_haze == 1.0
    with pytest.raises(PhotoSettingsError, match="ray_haze"):
        PhotoSettings(ray_haze=1.5)


# -- session 7: the haze correction only where the far picture shows the fog -------------------------------------------


def _far_lighter_road(fog: float, far: float, height: int = 96, width: int = 160,
                      horizon: float = 30.0) -> torch.Tensor:
    """:func:`_foggy_road`'s road (0.4 near the camera, ``fog`` at the horizon) under a far picture (the rows above
    the horizon: sky, trees, facades) of grey ``far``: ``far == fog`` is fog, which greys everything far alike; a
    darker ``far`` is a road lighter towards the horizon for another reason (a wet road's sheen, a lit patch) under
    a far picture that shows no fog."""
    image = _foggy_road(fog, height, width, horizon)
    image[:, : int(horizon) + 1] = far
    return image


def test_ray_haze_applies_in_fog_not_where_the_far_picture_shows_no_fog():
    """The same far-lighter road twice: under a fog-coloured far picture (fog-like) the fill follows the fitted fog
    and ends near the truth; under a dark far picture (rain-like: a wet sheen, not fog) the fit's fog is not the
    far picture's colour, no correction is added, and the fill is the uncorrected one (with the check off it
    would be corrected)."""
    from sdn3d.editing.photo.fill import fill_hole
    from sdn3d.editing.photo.road import road_haze

    vp = (80.0, 30.0)
    hole = torch.zeros(96, 160, dtype=torch.bool)
    hole[26:60, 65:95] = True
    far = (slice(None), slice(36, 48), slice(74, 86))
    # the rays alone (the hole covers the vanishing point: ray_vanishing='telea' would hand its middle to Telea)
    fixed = {"fill": "rays", "ray_grain": "fixed", "ray_texture": 0.0, "ray_vanishing": "near"}
    settings, off = PhotoSettings(**fixed), PhotoSettings(**fixed, ray_haze=0.0)
    assert settings.ray_haze_airlight == 0.25

    foggy = _far_lighter_road(0.8, far=0.8)
    assert road_haze(foggy, ~hole, hole, vp[1]) is not None
    truth = float(foggy[far].mean())
    on_fog = fill_hole(foggy, hole, settings, vanishing=vp)
    assert abs(float(on_fog[far].mean()) - truth) < 0.03 < abs(float(fill_hole(foggy, hole, off, vanishing=vp)[far]
                                                                    .mean()) - truth)

    sheen = _far_lighter_road(0.8, far=0.3)
    assert road_haze(sheen, ~hole, hole, vp[1]) is None
    assert road_haze(sheen, ~hole, hole, vp[1], airlight=1.0) is not None  # the check, not the fit, says no
    assert torch.equal(fill_hole(sheen, hole, settings, vanishing=vp), fill_hole(sheen, hole, off, vanishing=vp))
    unchecked = fill_hole(sheen, hole, PhotoSettings(**fixed, ray_haze_airlight=1.0), vanishing=vp)
    assert float((unchecked[far] - fill_hole(sheen, hole, off, vanishing=vp)[far]).abs().mean()) > 0.1


def test_road_haze_refuses_a_fit_whose_road_colour_is_off_the_scale():
    """A road that darkens a little towards the camera over rows where ``exp(-256 / r)`` is nearly 0 is fitted
    best by a tiny fog share with a huge amplitude: its road colour without fog (-1.5) is no colour, so no fit."""
    from sdn3d.editing.photo.road import road_haze

    rows = torch.arange(96, dtype=torch.float32)
    depth = (rows - 30.0).clamp(min=1.0)
    road = (0.5 - 2.0 * torch.exp(-256.0 / depth))[None, :, None].expand(3, 96, 160).clone()
    road[:, :31] = 0.5
    hole = torch.zeros(96, 160, dtype=torch.bool)
    hole[40:70, 65:95] = True
    assert road_haze(road, ~hole, hole, 30.0, airlight=1.0) is None
    gentle = (0.5 - 0.1 * torch.exp(-16.0 / depth))[None, :, None].expand(3, 96, 160).clone()  # a plausible one
    gentle[:, :31] = 0.5
    assert road_haze(gentle, ~hole, hole, 30.0, airlight=1.0) is not None


def test_ray_haze_airlight_setting_is_checked():
    with pytest.raises(PhotoSettingsError, match="ray_haze_airlight"):
        PhotoSettings(ray_haze_airlight=-0.1)


# -- session 14: a verge beside the hole is not blended into the road ----------------------------------------------


def _verge_beside_the_hole() -> tuple[torch.Tensor, torch.Tensor, tuple[float, float]]:
    """``(image, hole, vp)``: yellowish-grey road under a horizon at row 30, its vanishing point on the left
    (20, 30); a green verge just right of the hole (the rays' near side, away from the vanishing point), road left of
    it (their far side)."""
    image = torch.tensor([0.45, 0.44, 0.38])[:, None, None].expand(3, 96, 160).clone()
    image[:, 45:80, 110:150] = torch.tensor([0.45, 0.6, 0.2])[:, None, None]
    hole = torch.zeros(96, 160, dtype=torch.bool)
    hole[50:70, 70:110] = True
    return image, hole, (20.0, 30.0)


def test_a_verge_on_the_near_side_only_is_not_blended_into_the_road_on_the_ground():
    """verge='blend' fades the verge's green across the hole (the real frame's black car: a pale band of the verge
    across the far lane); verge='road' fills the hole's ground rows with the far side's road alone, and leaves rows
    above ``ground_row`` to the blend."""
    from sdn3d.editing.photo.road import road_lab, verge_like

    image, hole, vp = _verge_beside_the_hole()
    road = road_lab(torch.tensor([[0.45, 0.44, 0.38]]))[0]
    blend, _ = ray_fill(image, hole, vp, texture=0.0, road=road, verge="blend")
    on, _ = ray_fill(image, hole, vp, texture=0.0, road=road, verge="road")
    assert float(verge_like(blend[:, hole], road).float().mean()) > 0.2  # a green fade across the hole
    assert not bool(verge_like(on[:, hole], road).any())
    assert float((on[:, hole] - torch.tensor([0.45, 0.44, 0.38])[:, None]).abs().mean()) < 0.002
    high, _ = ray_fill(image, hole, vp, texture=0.0, road=road, verge="road", ground_row=60.0)
    assert torch.equal(high[:, 50:60], blend[:, 50:60])  # above the ground row: blended as before
    assert torch.equal(high[:, 60:], on[:, 60:])
    assert torch.equal(ray_fill(image, hole, vp, texture=0.0)[0], blend)  # no road given: the blend


def test_a_far_side_near_the_vanishing_point_does_not_end_the_verge(monkeypatch):
    """Where a ray's far side is nearer the vanishing point than FAR_RESOLVED of its near side, a verge strip along
    the road would be too narrow there to be seen: its road says nothing and the sides are blended as before."""
    import sdn3d.editing.photo.road as road_module
    from sdn3d.editing.photo.road import road_lab, verge_like

    image, hole, vp = _verge_beside_the_hole()
    hole[50:70, 25:110] = True  # reaching to within a few pixels of the vanishing point's column
    road = road_lab(torch.tensor([[0.45, 0.44, 0.38]]))[0]
    kept = verge_like(ray_fill(image, hole, vp, texture=0.0, road=road, verge="road")[0][:, hole], road)
    assert bool(kept.any())
    monkeypatch.setattr(road_module, "FAR_RESOLVED", 0.0)
    assert not bool(verge_like(ray_fill(image, hole, vp, texture=0.0, road=road, verge="road")[0][:, hole],
                               road).any())


def test_a_verge_seen_on_both_sides_still_crosses_the_hole():
    """A verge along the road, on both sides of the hole, is continued across it in either mode."""
    from sdn3d.editing.photo.road import road_lab

    image, hole, vp = _verge_beside_the_hole()
    image[:, 30:96, :] = torch.tensor([0.45, 0.6, 0.2])[:, None, None]  # grass everywhere below the horizon
    road = road_lab(torch.tensor([[0.45, 0.44, 0.38]]))[0]
    on, _ = ray_fill(image, hole, vp, texture=0.0, road=road, verge="road")
    assert torch.allclose(on, ray_fill(image, hole, vp, texture=0.0, road=road, verge="blend")[0])
    assert (on[:, hole] - torch.tensor([0.45, 0.6, 0.2])[:, None]).abs().max() < 0.01


def test_a_verge_tip_beyond_an_ended_verge_is_no_line_across_the_hole():
    """The near-side verge's rays mostly find road beyond the hole (the verge ended inside it), and a few find a small
    verge patch there (the real frame's black car: a traffic island's tip beyond the island): those few are filled
    with road as well, not with a thin line of verge joining the two (session 15's main drew 57 verge pixels)."""
    from sdn3d.editing.photo.road import road_lab, verge_like

    image, hole, vp = _verge_beside_the_hole()
    image[:, 46:50, 86:94] = torch.tensor([0.45, 0.6, 0.2])[:, None, None]  # the tip, on the far side of a few rays
    road = road_lab(torch.tensor([[0.45, 0.44, 0.38]]))[0]
    on, _ = ray_fill(image, hole, vp, texture=0.0, road=road, verge="road")
    blend, _ = ray_fill(image, hole, vp, texture=0.0, road=road, verge="blend")
    assert int(verge_like(blend[:, hole], road).sum()) > 300
    assert not bool(verge_like(on[:, hole], road).any())
    assert float((on[:, hole] - torch.tensor([0.45, 0.44, 0.38])[:, None]).abs().mean()) < 0.002


def test_a_verge_seen_beyond_the_hole_by_most_of_its_rays_still_crosses_it():
    """A far-side verge that most of the near-side verge's rays meet (a verge strip continuing behind the car) is
    continued across the hole where both sides show it."""
    from sdn3d.editing.photo.road import road_lab, verge_like

    image, hole, vp = _verge_beside_the_hole()
    image[:, 40:50, 60:110] = torch.tensor([0.45, 0.6, 0.2])[:, None, None]  # verge beyond every near-verge ray
    road = road_lab(torch.tensor([[0.45, 0.44, 0.38]]))[0]
    on, _ = ray_fill(image, hole, vp, texture=0.0, road=road, verge="road")
    assert int(verge_like(on[:, hole], road).sum()) > 300


def test_ray_verge_reaches_the_rays_through_fill_hole_and_is_checked():
    from sdn3d.editing.photo.fill import fill_hole
    from sdn3d.editing.photo.road import road_lab
    from sdn3d.editing.photo.transfer import GROUND_REACH, _ground_row

    image, hole, vp = _verge_beside_the_hole()
    road = road_lab(torch.tensor([[0.45, 0.44, 0.38]]))[0]
    fixed = {"fill": "rays", "ray_grain": "fixed", "ray_texture": 0.0, "ray_marks": 0.0, "ray_haze": 0.0}
    on = fill_hole(image, hole, PhotoSettings(**fixed, ray_verge="road"), vanishing=vp, road=road, ground_row=0.0)
    off = fill_hole(image, hole, PhotoSettings(**fixed, ray_verge="blend"), vanishing=vp, road=road, ground_row=0.0)
    unknown = fill_hole(image, hole, PhotoSettings(**fixed, ray_verge="road"), vanishing=vp, road=road)
    assert float((on[:, hole] - torch.tensor([0.45, 0.44, 0.38])[:, None]).abs().mean()) < 0.002
    assert not torch.equal(on, off) and torch.equal(unknown, off)  # no ground row known: the blend
    part = torch.zeros(96, 160, dtype=torch.bool)
    part[70:, 60:100] = True  # the footprint's far edge on row 70, the horizon on row 30
    K = torch.tensor([[100.0, 0.0, 80.0], [0.0, 100.0, 30.0], [0.0, 0.0, 1.0]], dtype=torch.float64)
    assert _ground_row(part, K) == pytest.approx(30.0 + 40.0 / GROUND_REACH)
    assert _ground_row(torch.zeros_like(part), K) is None
    assert PhotoSettings().ray_verge == "edges"
    with pytest.raises(PhotoSettingsError, match="ray_verge"):
        PhotoSettings(ray_verge="grass")


def _far_car_straight_ahead():
    """``(image (3, 64, 96), hole (64, 96), vp)``: a foggy road (its colour goes to the fog's towards the horizon,
    row 24) under a fogged treeline, the vanishing point (48, 24) inside a box-shaped hole (a far car straight ahead,
    as the tuning deletes' cars that stood over the vanishing point), its near edge on row 44."""
    height, width, horizon = 64, 96, 24
    rows = torch.arange(height, dtype=torch.float32)[:, None, None].expand(height, width, 1)
    depth = (1 - torch.exp(-(rows - horizon).clamp(min=0) / 6.0))
    fog, asphalt = torch.tensor([0.8, 0.8, 0.8]), torch.tensor([0.35, 0.35, 0.33])
    trees = torch.tensor([0.7, 0.75, 0.7])
    image = torch.where(rows >= horizon, fog + (asphalt - fog) * depth, trees).permute(2, 0, 1).contiguous()
    hole = torch.zeros(height, width, dtype=torch.bool)
    hole[20:44, 36:60] = True
    image[:, hole] = torch.tensor([0.1, 0.1, 0.1])[:, None]  # the car
    return image, hole, (48.0, float(horizon))


def test_a_hole_over_the_vanishing_point_is_filled_from_near_sides_only_near_them():
    from sdn3d.editing.photo.fill import fill_hole, inpaint
    from sdn3d.editing.photo.road import NEAR_REACH

    image, hole, vp = _far_car_straight_ahead()
    _, reached_near = ray_fill(image, hole, vp, texture=0.0, vanishing="near")
    _, reached = ray_fill(image, hole, vp, texture=0.0, vanishing="telea")
    assert torch.equal(reached_near, hole)  # every ray has its near side
    assert NEAR_REACH == 2.0
    # straight below the vanishing point (48, 24), the near side on row 44: a pixel at most twice as deep as it
    # (at least 10 rows below the point) keeps the ray, a deeper one is left to Telea; straight above it, the near
    # side is the treeline's row 19
    column = reached[:, 48]
    assert not bool(column[22:34].any()) and bool(column[34:44].all()) and bool(column[20:22].all())
    assert not bool(reached[22:27, 45:52].any())  # around the vanishing point: no ray at all
    assert bool(reached[43, 36:60].all())  # just above the near edge: every ray
    fixed = {"fill": "rays", "ray_grain": "fixed", "ray_texture": 0.0, "ray_marks": 0.0, "ray_haze": 0.0}
    out = fill_hole(image, hole, PhotoSettings(**fixed, ray_vanishing="telea"), vanishing=vp)
    settings = PhotoSettings(**fixed)
    rays, _ = ray_fill(image, hole, vp, sigma=settings.ray_blur, texture=0.0, along=settings.ray_span, marks=0.0,
                       vanishing="telea")
    assert torch.equal(out[:, reached], rays[:, reached])
    assert torch.equal(out, inpaint(rays, hole & ~reached, "telea", settings.inpaint_radius))


def test_a_ray_stopped_by_another_object_before_the_vanishing_point_keeps_its_near_side():
    image, hole, vp = _far_car_straight_ahead()
    side = torch.zeros_like(hole)
    side[40:60, 10:30] = True  # a hole down and left of the vanishing point: its rays leave it towards the point
    other = torch.zeros_like(hole)
    other[30:40, 20:46] = True  # another object on those rays, between the hole and the point
    _, reached = ray_fill(image, side, vp, keep_out=other, texture=0.0, vanishing="telea")
    assert torch.equal(reached, side)
    assert PhotoSettings().ray_vanishing == "telea"
    with pytest.raises(PhotoSettingsError, match="ray_vanishing"):
        PhotoSettings(ray_vanishing="far")
    with pytest.raises(ValueError, match="vanishing"):
        ray_fill(image, side, vp, vanishing="far")


def _occluder_scene(meta: dict):
    """``(scene, image, edited)``: SIDE partly hidden behind NEAR, the scene's ``meta`` as given, NEAR deleted."""
    from tests.test_photo import FRAME, _k_input, _scene, _surface_colors

    scene = _scene([NEAR, SIDE])
    scene = scene.replace(meta=meta)
    image, _ = _surface_colors(scene, FRAME.input_size[::-1], _k_input())
    return scene, image, apply_edits(scene, [Delete(12001)])


def _with(**changes) -> PhotoSettings:
    return PhotoSettings(**{**SETTINGS.to_dict(), **changes})


def test_a_predicted_car_behind_is_completed_only_by_a_small_share_of_its_shown_pixels():
    """Session 23 (issue 40, removals on predictions): the car behind a deleted one is completed into the freed
    pixels from ground-truth masks whatever their number; where its mask is the semantic branch's prediction, only
    while the pixels it draws there are at most ``grow_predicted_share`` of its mask's pixels in the input (else the
    fill keeps them all, as the 2D paste's); an object named by a box in such a scene is not capped."""
    from sdn3d.box_objects import BoxFit, MaskSource, PoseSource
    from sdn3d.editing.photo.transfer import PhotoSource
    from tests.test_photo import FRAME

    oracle, image, edited = _occluder_scene({"proposals": "gt"})
    assert int(edited.objects.mask[0].sum()) > int(oracle.objects.mask[1].sum())  # apply_edits completed SIDE
    drawn = _drawn(render_photo(image, FRAME, oracle, edited, settings=SETTINGS))
    assert int(drawn.sum()) > 50  # ground-truth masks: SIDE drawn into the freed pixels
    shown = int((PhotoSource(image, FRAME, oracle, settings=SETTINGS).src_ids == 12002).sum())
    share = int(drawn.sum()) / shown  # the freed pixels SIDE draws against its shown pixels (0.61 here)
    assert 0.5 < share < 2.0

    predicted, image, edited = _occluder_scene({"proposals": "semantic"})
    # past the share (here the default 0.5): none of it is drawn, the fill keeps every one of those pixels
    now = render_photo(image, FRAME, predicted, edited, settings=SETTINGS)
    assert int(_drawn(now).sum()) == 0 and 12002 not in now.objects
    assert bool((now.source[drawn] == FILL).all())
    for capped in (0.99 * share, 0.0):
        again = render_photo(image, FRAME, predicted, edited, settings=_with(grow_predicted_share=capped))
        assert torch.equal(again.source, now.source)
    assert torch.equal(_drawn(render_photo(image, FRAME, predicted, edited,
                                           settings=_with(grow_predicted_share=1.01 * share))), drawn)
    oracle, image, edited = _occluder_scene({"proposals": "gt"})  # ground-truth masks are never capped
    assert torch.equal(_drawn(render_photo(image, FRAME, oracle, edited, settings=_with(grow_predicted_share=0.0))),
                       drawn)

    box = BoxFit(12002, (0.0, 0.0, 10.0, 10.0), MaskSource.GRABCUT, False, 70, PoseSource.ROAD_PLANE, 0.9, False, 70,
                 64)
    boxed, image, edited = _occluder_scene({"proposals": "semantic", "boxes": [box]})
    assert torch.equal(_drawn(render_photo(image, FRAME, boxed, edited, settings=_with(grow_predicted_share=0.0))),
                       drawn)


def test_predicted_masks_names_the_semantic_branchs_objects_less_the_boxes():
    from sdn3d.box_objects import BoxFit, MaskSource, PoseSource
    from sdn3d.proposals import predicted_masks

    ids = torch.tensor([12001, 12002, 13003])
    assert predicted_masks({"proposals": "semantic"}, ids).tolist() == [True, True, True]
    assert predicted_masks({"proposals": "gt"}, ids).tolist() == [False, False, False]
    assert predicted_masks({}, ids).tolist() == [False, False, False]
    box = BoxFit(12002, (0.0, 0.0, 10.0, 10.0), MaskSource.GRABCUT, False, 70, PoseSource.ROAD_PLANE, 0.9, False, 70,
                 64)
    assert predicted_masks({"proposals": "semantic", "boxes": [box]}, ids).tolist() == [True, False, True]
    assert predicted_masks({"proposals": "semantic", "boxes": [box.to_json()]}, ids).tolist() == [True, False, True]
    assert PhotoSettings().grow_predicted_share == 0.5
    for bad in ("no", -0.1, True):
        with pytest.raises(PhotoSettingsError, match="grow_predicted_share"):
            PhotoSettings(grow_predicted_share=bad)
