"""The faint edge of a removed car's shadow (issue 41: residual darkening under 5 %; session 27 shadow41): road a
few per cent darker than its row's lit road around the filled shadow (penumbra, blocked skylight), which the shadow
test at ``photo.shadow_light`` leaves, is relit with ``photo.faint_light``
(:func:`~sdn3d.editing.photo.fill.relight_faint_shadow`, :func:`~sdn3d.editing.photo.road.road_shade`)."""

from __future__ import annotations

import pytest
import torch

from sdn3d.editing.photo.fill import relight_faint_shadow
from sdn3d.editing.photo.road import road_colours, road_shade, shadowed_road
from sdn3d.editing.photo.settings import PhotoSettings, PhotoSettingsError

pytestmark = pytest.mark.usefixtures("one_torch_thread")

ROAD = 0.5


def _scene() -> dict[str, torch.Tensor]:
    """A grey road ``(3, 96, 160)`` with grain; the removed car's hole (rows 20-69, columns 40-99) whose lower rows
    are its dark shadow; around the hole's lower half a faint halo at 0.92 of the road (rows 45-79, columns 30-109,
    outside the hole); a faint patch apart from it (rows 84-89, columns 130-139, the same darkness); the search region
    (the fitted footprint grown) over the hole's lower half and the halo."""
    gen = torch.Generator().manual_seed(0)
    image = ROAD + 0.02 * torch.randn(1, 96, 160, generator=gen).expand(3, -1, -1).clone()  # grey grain
    hole = torch.zeros(96, 160, dtype=torch.bool)
    hole[20:70, 40:100] = True
    halo = torch.zeros_like(hole)
    halo[45:80, 30:110] = True
    halo &= ~hole
    patch = torch.zeros_like(hole)
    patch[84:90, 130:140] = True
    image[:, halo | patch] *= 0.92
    image[:, 55:70, 40:100] = 0.2  # the car's shadow under it, in the hole
    search = torch.zeros_like(hole)
    search[45:84, 28:112] = True
    return {"image": image.clamp(0, 1), "hole": hole, "halo": halo, "patch": patch, "search": search}


def _lit_and_road(s: dict[str, torch.Tensor]) -> tuple[torch.Tensor, torch.Tensor]:
    grown = torch.nn.functional.max_pool2d((s["hole"] | s["search"]).float()[None, None], 7, 1, 3)[0, 0].bool()
    lit = ~grown & ~s["patch"]
    return lit, road_colours(s["image"], lit)


def test_road_shade_is_the_share_of_the_rows_lit_road_and_shadowed_road_its_test():
    s = _scene()
    lit, road = _lit_and_road(s)
    within = torch.ones_like(s["hole"])
    shade = road_shade(s["image"], road, within, lit, luma=True)
    assert abs(float(shade[s["halo"]].nanmedian()) - 0.92) < 0.02
    assert abs(float(shade[lit].nanmedian()) - 1.0) < 0.01
    light = road_shade(s["image"], road, within, lit)  # CIE L: the same order, a smaller dip
    assert float(light[s["halo"]].nanmedian()) < 0.99
    # shadowed_road is road_shade's test: the dark shadow in, the faint halo out.
    dark = shadowed_road(s["image"], road, within, lit, 0.8)
    assert bool(dark[60:70, 50:90].all()) and not bool(dark[s["halo"]].any())
    assert torch.equal(dark, torch.nan_to_num(light, nan=2.0) < 0.8)


def test_the_faint_halo_touching_the_hole_is_relit_to_the_road_and_a_patch_apart_stays():
    s = _scene()
    lit, road = _lit_and_road(s)
    zone = s["search"] & ~s["hole"] | s["patch"]
    shade = road_shade(s["image"], road, zone, lit, luma=True)
    out, gain = relight_faint_shadow(s["image"], shade, zone, s["hole"], 0.95, 0.8)
    inner = s["halo"] & ~torch.nn.functional.max_pool2d((~s["halo"]).float()[None, None], 7, 1, 3)[0, 0].bool()
    assert float(s["image"][:, inner].mean()) < 0.93 * ROAD
    assert abs(float(out[:, inner].mean()) - ROAD) < 0.02 * ROAD  # relit to the road's lightness
    assert torch.equal(out[:, s["patch"]], s["image"][:, s["patch"]])  # apart from the hole: stays
    assert torch.equal(out[:, s["hole"]], s["image"][:, s["hole"]])  # the hole is the fill's
    assert bool((gain[~zone] == 1).all())
    # A gain, not a colour: the road's grain stays (its spread grows with the gain, ~1/0.92).
    ratio = float(out[:, inner].std() / s["image"][:, inner].std())
    assert 1.0 < ratio < 1.15
    # The halo lighter than the upper share is not touched.
    same, ones = relight_faint_shadow(s["image"], shade, zone, s["hole"], 0.85, 0.8)
    assert torch.equal(same, s["image"]) and bool((ones == 1).all())


def test_a_delete_relights_the_faint_halo_with_faint_light_and_leaves_it_without():
    import sdn3d.editing.photo.transfer as transfer

    s = _scene()
    lit, road = _lit_and_road(s)
    ring = lit
    objects = torch.zeros_like(s["hole"])
    vp = (80.0, -2000.0)
    inner = s["halo"] & (torch.arange(96) >= 50)[:, None] & ~torch.nn.functional.max_pool2d(
        (~s["halo"]).float()[None, None], 5, 1, 2)[0, 0].bool()
    plain, matte_plain = transfer._rays_with_effects(s["image"], s["hole"], objects, s["search"], ring, road,
                                                     PhotoSettings(fill="rays", faint_light=0.0), vp)
    assert float(plain[:, inner].mean()) < 0.93 * ROAD  # 0: the halo stays, as before
    assert not bool((matte_plain[inner] > 0).any())
    relit, matte = transfer._rays_with_effects(s["image"], s["hole"], objects, s["search"], ring, road,
                                               PhotoSettings(fill="rays"), vp)  # the default
    assert abs(float(relit[:, inner].mean()) - ROAD) < 0.02 * ROAD
    assert bool((matte[inner] > 0.02).all())  # render_photo marks them relit
    assert not bool((matte[s["hole"]] > 0).any())  # the hole (the dark shadow with it) is the fill's, not relit
    assert torch.equal(relit[:, s["patch"]], s["image"][:, s["patch"]])


def test_faint_light_is_checked_by_name():
    assert PhotoSettings().faint_light == 0.98
    assert PhotoSettings(faint_light=0.0).faint_light == 0.0
    for bad in (0.5, 0.8, 1.2, -0.1, True, "0.9"):
        with pytest.raises(PhotoSettingsError, match="faint_light"):
            PhotoSettings(faint_light=bad)


def test_a_road_lit_unevenly_across_its_rows_is_not_taken_for_faint_shadow(monkeypatch):
    """The real frame's road darkens to the right: against its row's lit road (most of it on the lighter left) the
    darker right is shade (``local`` 0), against the lit road beside it (``local``, what a delete uses) it is road,
    and a delete leaves it."""
    import sdn3d.editing.photo.transfer as transfer

    s = {k: v[..., :131] for k, v in _scene().items()}  # lit road: 25 columns on the left, 15 on the right
    ramp = torch.ones(131)
    ramp[96:] = torch.cat([torch.linspace(1.0, 0.88, 17), torch.full((18,), 0.88)])  # darker past the car
    s["image"] = (s["image"] / torch.where(s["halo"] | s["patch"], 0.92, 1.0)) * ramp  # no halo, no patch
    s["image"][:, 55:70, 40:100] = 0.2
    lit, road = _lit_and_road(s)
    zone = s["search"] & ~s["hole"]
    right = zone & (torch.arange(131) >= 104)[None]
    by_row = road_shade(s["image"], road, zone, lit, luma=True)
    around = road_shade(s["image"], road, zone, lit, luma=True, local=10.0)
    assert float(by_row[right].nanmedian()) < 0.95  # the darker side against the whole row
    assert float(around[right].nanmedian()) > 0.99  # against the road beside it: lit road, no shade
    plain = PhotoSettings(fill="rays", faint_light=0.0)
    before, _ = transfer._rays_with_effects(s["image"], s["hole"], torch.zeros_like(s["hole"]), s["search"], lit,
                                            road, plain, (65.0, -2000.0))
    after, _ = transfer._rays_with_effects(s["image"], s["hole"], torch.zeros_like(s["hole"]), s["search"], lit,
                                           road, PhotoSettings(fill="rays"), (65.0, -2000.0))
    changed = int(((after != before).any(0) & ~s["hole"]).sum())
    monkeypatch.setattr(transfer, "FAINT_REFERENCE", 0.0)  # the row's lit road
    by_row_after, _ = transfer._rays_with_effects(s["image"], s["hole"], torch.zeros_like(s["hole"]), s["search"],
                                                  lit, road, PhotoSettings(fill="rays"), (65.0, -2000.0))
    changed_by_row = int(((by_row_after != before).any(0) & ~s["hole"]).sum())
    assert changed < 0.05 * int(zone.sum())  # next to nothing relit (a few grain pixels beside the hole)
    assert changed_by_row > 4 * changed, (changed_by_row, changed)
