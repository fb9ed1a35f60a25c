"""The photo appearance (:mod:`sdn3d.editing.photo`): the input's own pixels carried through each edited object's
3D shape, checked on pictures whose every surface point has a known colour."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import torch

from sdn3d.editing.apply import Delete, Move, Rotate, SetCode, apply_edits
from sdn3d.editing.frame import PixelFrame, input_intrinsics, upsample_ids
from sdn3d.editing.photo.fill import inpaint
from sdn3d.editing.photo.light import fit_light
from sdn3d.editing.photo.recolor import paints, recolor_pixels
from sdn3d.editing.photo.settings import FALLBACK, FILL, INPUT, MIRROR, PHOTO, PhotoSettings, PhotoSettingsError
from sdn3d.editing.photo.transfer import render_photo
from sdn3d.math3d.camera import Intrinsics
from sdn3d.meshes.bank import default_bank
from sdn3d.render.rasterize import rasterize_meshes
from sdn3d.render.settings import RasterSettings
from sdn3d.scene.code import ObjectTable, SceneCode, SceneObject
from sdn3d.scene.maps import compose_instances, posed_meshes

WORK = (128, 64)  # working size (W, H)
INPUT_SIZE = (256, 128)  # the input: twice the working size
FRAME = PixelFrame(INPUT_SIZE, WORK)
K_WORK = Intrinsics(100.0, 100.0, 63.5, 31.5, width=WORK[0], height=WORK[1])
BACKGROUND = 0.45
#: The 3D transfer alone: no light, no contact shadow, no paste of the input's mask for a view that hardly turns, no
#: outline grown past the template's.
NO_LIGHT = PhotoSettings(relight=False, contact_shadow=0.0, fill="telea", unseen="body", mask_view_deg=0.0,
                         outline_grow=0.0)


def _scene(objects: list[SceneObject]) -> SceneCode:
    """A scene of ``objects`` whose masks are their rendered, depth-composed silhouettes at the working size."""
    h, w = WORK[1], WORK[0]
    table = ObjectTable.from_objects(objects, h, w)
    bare = SceneCode(K_WORK, torch.zeros(h, w, dtype=torch.long), "vkitti", table, background_codes={})
    ids = compose_instances(bare)
    masks = ids[None] == table.instance_id[:, None, None]
    return bare.replace(objects=table.replace(mask=masks, has_mask=torch.ones(len(table), dtype=torch.bool)))


def _surface_colors(scene: SceneCode, size: tuple[int, int], K: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor]:
    """``(image (3, H, W), covered (H, W))``: every object painted by the colour of its canonical surface point
    (``0.2 + 0.6 * (x + 0.5, y + 0.5, 2 |z|)``: smooth over the surface, the same on both sides of the vehicle's
    left-right plane), over a constant background, rasterized at ``size (H, W)`` with ``K``."""
    bank = default_bank()
    rows, verts, faces = posed_meshes(scene.objects, bank)
    canon, _ = bank.gather(scene.objects.template_id[rows])
    frags = rasterize_meshes(verts.double(), faces, K, RasterSettings(image_size=size),
                             mesh_to_image=torch.zeros(len(rows), dtype=torch.long), batch_size=1)
    hit = frags.mask[0]
    pix = hit.view(-1).nonzero().flatten()
    mesh = frags.pix_to_mesh.view(-1)[pix]
    face = frags.pix_to_face.view(-1)[pix] - mesh * faces.shape[1]
    vid = faces[mesh, face]
    point = (frags.bary.view(-1, 3)[pix].double()[..., None] * canon[mesh[:, None], vid].double()).sum(1)
    color = 0.2 + 0.6 * torch.stack([point[:, 0] + 0.5, point[:, 1] + 0.5, 2 * point[:, 2].abs()], 1)
    image = torch.full((size[0] * size[1], 3), BACKGROUND, dtype=torch.float64)
    image[pix] = color.clamp(0, 1)
    return image.view(size[0], size[1], 3).permute(2, 0, 1).float(), hit


def _k_input() -> torch.Tensor:
    return input_intrinsics(K_WORK, FRAME).matrix(dtype=torch.float64)


CAR = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.4, location=(-1.0, 1.6, 12.0))
FAR_CAR = SceneObject(12002, template_id=1, dims=(4.2, 1.6, 1.9), ry=-1.2, location=(3.0, 1.6, 20.0))


def test_input_intrinsics_project_where_the_transform_says():
    frame = PixelFrame((300, 100), (128, 64), scaled_size=(192, 64), offset=(32, 0))
    big = input_intrinsics(K_WORK, frame)
    point = torch.tensor([1.3, -0.4, 9.0])
    def project(k: Intrinsics) -> tuple[float, float]:
        return (k.fx * point[0] / point[2] + k.cx).item(), (k.fy * point[1] / point[2] + k.cy).item()

    (u_w, v_w), (u_i, v_i) = project(K_WORK), project(big)
    assert frame.to_input((u_w, v_w)) == pytest.approx((u_i, v_i), abs=1e-4)  # float32 intrinsics
    ids = torch.arange(64 * 128).view(64, 128)
    up = upsample_ids(ids, frame)
    assert up.shape == (100, 300) and int(up[50, 0]) == 0  # left of the crop: nothing there
    j, i = 150, 40  # an input pixel inside the crop lands on its nearest working pixel
    u, v = frame.to_working((j, i))
    assert int(up[i, j]) == int(ids[round(v), round(u)])


def test_no_edit_gives_the_input_bit_for_bit():
    scene = _scene([CAR, FAR_CAR])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    original = (image * 255).round().to(torch.uint8)
    result = render_photo(original, FRAME, scene, apply_edits(scene, []))
    assert torch.equal(result.image, original) and bool((result.source == INPUT).all()) and result.objects == {}


@pytest.mark.parametrize("turn_deg", [0.0, 25.0, 180.0])
def test_moved_and_turned_car_carries_its_own_surface_colours(turn_deg):
    """Where the photo path says it took a pixel from the photo (or its mirror image), the colour is the one the
    car's surface point has: the transfer lands on the same point of the shape."""
    scene = _scene([CAR, FAR_CAR])
    K = _k_input()
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], K)
    ops = [Move(12001, (50.0, 40.0))] + ([Rotate(12001, math.radians(turn_deg))] if turn_deg else [])
    edited = apply_edits(scene, ops)
    expected, covered = _surface_colors(edited.replace(objects=edited.objects.select(torch.tensor([0]))
                                                       if edited.objects.instance_id[0] == 12001 else
                                                       edited.objects.select(torch.tensor([1]))),
                                        INPUT_SIZE[::-1], K)
    result = render_photo(image, FRAME, scene, edited, settings=NO_LIGHT)
    seen = (result.source == PHOTO) | (result.source == MIRROR)
    # Interior pixels only: the silhouette's rim samples the background bilinearly.
    inner = torch.nn.functional.max_pool2d((~covered)[None, None].float(), 5, 1, 2)[0, 0] == 0
    check = seen & inner
    assert int(check.sum()) > 300
    err = (result.image - expected).abs().amax(0)[check]
    assert float(err.mean()) < 0.02 and float(torch.quantile(err, 0.95)) < 0.06
    shares = result.objects[12001]
    assert shares["photo"] + shares["mirror"] + shares["part"] + shares["fallback"] == pytest.approx(1.0, abs=1e-3)
    if turn_deg == 180.0:  # the side the photo showed now faces away: the mirror supplies the near side
        assert shares["mirror"] > 0.3
    else:  # the surfaces the photo saw edge-on (min_view_cos) are not taken from it
        assert shares["photo"] > 0.55
    # Nothing moved but the car: far from it and from where it was, the input's pixels.
    changed = result.source != INPUT
    assert torch.equal(result.image[:, ~changed], image[:, ~changed])


def test_a_side_the_photo_saw_edge_on_is_not_stretched_over_a_turned_car():
    """A car seen from behind, a little to the left, shows its right side nearly edge-on (a few pixels wide); turned
    by 90 degrees, that side faces the camera and must come from the body colour, not from those few pixels
    stretched over it."""
    behind = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=-math.pi / 2, location=(-2.0, 1.6, 12.0))
    scene = _scene([behind])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    edited = apply_edits(scene, [Rotate(12001, math.pi / 2)])
    shares = render_photo(image, FRAME, scene, edited, settings=NO_LIGHT).objects[12001]
    assert shares["photo"] + shares["mirror"] < 0.1 and shares["fallback"] > 0.9
    stretched = render_photo(image, FRAME, scene, edited, settings=dataclasses.replace(NO_LIGHT, min_view_cos=0.0))
    assert stretched.objects[12001]["photo"] + stretched.objects[12001]["mirror"] > 0.3  # what the check prevents
    with pytest.raises(PhotoSettingsError, match="min_view_cos"):
        PhotoSettings(min_view_cos=1.5)


def test_a_moved_car_passes_behind_a_nearer_one():
    near = SceneObject(12003, template_id=2, dims=(4.0, 1.5, 1.8), ry=0.0, location=(0.5, 1.6, 8.0))
    far = SceneObject(12004, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.3, location=(-6.0, 1.6, 16.0))
    scene = _scene([near, far])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    ids = upsample_ids(compose_instances(scene), FRAME)
    behind = Move(12004, (45.0, 31.5 + 100 * 0.85 / 16))  # same distance, half behind the near car
    result = render_photo(image, FRAME, scene, apply_edits(scene, [behind]), settings=NO_LIGHT)
    near_px = ids == 12003
    inner = torch.nn.functional.max_pool2d((~near_px)[None, None].float(), 3, 1, 1)[0, 0] == 0
    assert bool(inner.any()) and torch.equal(result.image[:, inner], image[:, inner])  # the near car stays in front
    assert int(((result.source == PHOTO) | (result.source == MIRROR) | (result.source == FALLBACK)).sum()) > 50


def test_delete_fills_the_footprint_and_its_shadow_band_from_the_road():
    scene = _scene([CAR])
    image, covered = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    rows = torch.arange(INPUT_SIZE[1], dtype=torch.float32)[:, None].expand(INPUT_SIZE[1], INPUT_SIZE[0])
    road = (0.3 + 0.4 * rows / INPUT_SIZE[1])[None].expand(3, -1, -1)  # a smooth vertical gradient
    image = torch.where(covered[None], image, road)
    for fill in ("telea", "patchmatch"):
        result = render_photo(image, FRAME, scene, apply_edits(scene, [Delete(12001)]),
                              settings=PhotoSettings(fill=fill, delete_effects=False))  # the plain fill
        hole = result.source == FILL
        assert bool(hole[covered].all())  # the whole car is refilled
        below = hole & ~covered
        assert bool(below.any())  # with a band of road around and under it (the old contact shadow)
        err = (result.image - road).abs()[:, hole]
        assert float(err.mean()) < 0.04, fill
        assert torch.equal(result.image[:, ~hole], image[:, ~hole])


def test_inpaint_handles_holes_at_the_frame_edge():
    image = torch.full((3, 40, 60), 0.6)
    hole = torch.zeros(40, 60, dtype=torch.bool)
    hole[:8, :10] = True  # top-left corner: OpenCV needs the one-pixel pad
    image[:, hole] = 0.0
    for method in ("telea", "patchmatch", "auto"):
        out = inpaint(image, hole, method)
        assert float((out[:, hole] - 0.6).abs().max()) < 0.02, method
    with pytest.raises(PhotoSettingsError, match="'telea', 'patchmatch' or 'auto'"):
        inpaint(image, hole, "blur")


def test_auto_fill_uses_telea_for_thin_gaps_and_patchmatch_for_large_holes(monkeypatch):
    import sdn3d.editing.photo.fill as photo

    used = []
    real = photo._inpaint_part
    monkeypatch.setattr(photo, "_inpaint_part", lambda image, part, how, *a: used.append(how) or real(image, part,
                                                                                                   how, *a))
    image = torch.rand(3, 80, 120, generator=torch.Generator().manual_seed(0))
    hole = torch.zeros(80, 120, dtype=torch.bool)
    hole[10:13, 5:60] = True  # a thin gap: 3 px
    hole[40:70, 60:110] = True  # a large hole: 30 x 50 px
    inpaint(image, hole, "auto")
    assert sorted(used) == ["patchmatch", "telea"]


def test_fit_light_finds_the_direction_with_an_albedo_per_object():
    gen = torch.Generator().manual_seed(1)
    normals = torch.nn.functional.normalize(torch.randn(3000, 3, generator=gen), dim=1)
    groups = torch.randint(0, 3, (3000,), generator=gen)
    albedo = torch.tensor([0.3, 0.6, 0.9])[groups]
    light = torch.nn.functional.normalize(torch.tensor([0.4, -0.7, -0.5]), dim=0)
    y = albedo * (0.25 + 0.75 * (normals @ light).clamp(min=0))
    fit = fit_light(y[:, None].expand(-1, 3), normals, groups)
    assert float(fit.direction @ light) > 0.97 and fit.ambient == pytest.approx(0.25, abs=0.06) and fit.gain > 0.5
    assert fit_light(y[:10, None].expand(-1, 3), normals[:10], groups[:10]) is None  # too few pixels


def test_relight_darkens_a_side_turned_away_from_the_light():
    """A car lit from its left-front: after a half turn the bright side faces away, and the re-shaded pixels are
    darker than the photo's bright side was (the shading follows the pose)."""
    scene = _scene([CAR])
    K = _k_input()
    bank = default_bank()
    rows, verts, faces = posed_meshes(scene.objects, bank)
    frags = rasterize_meshes(verts.double(), faces, K, RasterSettings(image_size=INPUT_SIZE[::-1]),
                             mesh_to_image=torch.zeros(1, dtype=torch.long), batch_size=1)
    from sdn3d.render.maps import normal_map

    normals = normal_map(frags, verts.double(), faces)[0]  # (3, H, W)
    light = torch.nn.functional.normalize(torch.tensor([-0.6, -0.6, -0.5], dtype=torch.float64), dim=0)
    shade = 0.3 + 0.7 * (normals * light[:, None, None]).sum(0).clamp(min=0)
    image = torch.where(frags.mask[0][None], (0.8 * shade)[None].expand(3, -1, -1), torch.tensor(BACKGROUND,
                                                                                                   dtype=torch.float64))
    image = image.float()
    turned = apply_edits(scene, [Rotate(12001, math.pi)])
    lit = render_photo(image, FRAME, scene, turned, settings=PhotoSettings(relight=True, contact_shadow=0.0,
                                                                           outline_grow=0.0))
    flat = render_photo(image, FRAME, scene, turned, settings=NO_LIGHT)
    assert lit.light is not None and float(lit.light.direction @ light.float()) > 0.9
    drawn = (lit.source == PHOTO) | (lit.source == MIRROR)
    # The turned car shows the side that was dark; copied as it was it keeps the bright side's light.
    t_rows, t_verts, t_faces = posed_meshes(turned.objects, bank)
    t_frags = rasterize_meshes(t_verts.double(), t_faces, K, RasterSettings(image_size=INPUT_SIZE[::-1]),
                               mesh_to_image=torch.zeros(1, dtype=torch.long), batch_size=1)
    t_shade = 0.8 * (0.3 + 0.7 * (normal_map(t_frags, t_verts.double(), t_faces)[0]
                                  * light[:, None, None]).sum(0).clamp(min=0))
    err_lit = (lit.image[0] - t_shade.float()).abs()[drawn].mean()
    err_flat = (flat.image[0] - t_shade.float()).abs()[drawn].mean()
    assert float(err_lit) < 0.7 * float(err_flat)


def test_recolor_repaints_the_body_and_keeps_windows_and_shading():
    gen = torch.Generator().manual_seed(0)
    body = torch.tensor([0.85, 0.85, 0.87]) * torch.linspace(0.6, 1.0, 400)[:, None]
    glass = torch.tensor([0.08, 0.09, 0.12]) + 0.02 * torch.rand(150, 3, generator=gen)
    colors = torch.cat([body, glass])
    new, is_body, stats = recolor_pixels(colors, (0.70, 0.08, 0.08))
    assert bool(is_body[:400].all()) and not bool(is_body[400:].any())
    assert torch.equal(new[400:], colors[400:]) and stats["delta_e"] < 3
    # the body's shading survives: its luminance still rises monotonically along the ramp
    lum = new[:400] @ torch.tensor([0.2126, 0.7152, 0.0722])
    assert float((lum[1:] - lum[:-1] >= -1e-4).float().mean()) > 0.98 and float(lum[-1] - lum[0]) > 0.05
    assert float(new[:400, 0].mean()) > 2 * float(new[:400, 1].mean())  # red


def test_recolor_in_render_photo_reports_the_colour_difference():
    scene = _scene([CAR])
    image, covered = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    op = SetCode(12001, (0.0,) * 5, (0.10, 0.25, 0.70))
    assert paints([op, Delete(5)]) == {12001: (0.10, 0.25, 0.70)}
    result = render_photo(image, FRAME, scene, apply_edits(scene, [op]), settings=NO_LIGHT, recolor=paints([op]))
    info = result.objects[12001]["recolor"]
    assert info["delta_e"] < 5 and 0.2 < info["body_share"] <= 1
    assert not torch.equal(result.image[:, covered], image[:, covered])
    near = torch.nn.functional.max_pool2d(covered[None, None].float(), 7, 1, 3)[0, 0] > 0
    assert torch.equal(result.image[:, ~near], image[:, ~near])  # only the car's pixels change (its mask's rim)


def test_an_object_moved_out_of_the_picture_warns_and_does_not_crash():
    scene = _scene([CAR, FAR_CAR])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    gone = apply_edits(scene, [Move(12001, (127.0, 63.0))])
    gone = gone.replace(objects=gone.objects.replace(location=gone.objects.location
                                                     + torch.tensor([[40.0, 0.0, 0.0], [0.0, 0.0, 0.0]])))
    result = render_photo(image, FRAME, scene, gone, settings=NO_LIGHT)
    assert any("12001" in w and "outside the picture" in w for w in result.warnings)
    assert bool((result.source == FILL).any())  # its old place is still filled


def test_an_object_moved_wholly_behind_another_is_said_to_be_hidden_not_outside():
    scene = _scene([CAR, FAR_CAR])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    moved = scene.replace(objects=scene.objects.replace(location=scene.objects.location.clone()))
    moved.objects.location[0] = torch.tensor([6.75, 1.6, 45.0])  # straight behind the other car, in the picture
    result = render_photo(image, FRAME, scene, moved, settings=NO_LIGHT)
    said = [w for w in result.warnings if "12001" in w and "nothing drawn" in w]
    assert said and "hidden behind nearer objects" in said[0] and "outside" not in said[0]


def test_a_hidden_object_is_drawn_from_its_body_colour_with_a_warning():
    scene = _scene([CAR])
    hidden = scene.replace(objects=scene.objects.replace(mask=torch.zeros_like(scene.objects.mask)))
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    result = render_photo(image, FRAME, hidden, apply_edits(hidden, [Move(12001, (40.0, 40.0))]), settings=NO_LIGHT)
    assert result.objects[12001]["fallback"] == pytest.approx(1.0)
    assert any("12001" in w and "none of its surface is visible" in w for w in result.warnings)


def test_photo_settings_are_checked_by_name():
    with pytest.raises(PhotoSettingsError, match="photo.fill must be one of"):
        PhotoSettings(fill="lama")
    with pytest.raises(PhotoSettingsError, match="photo.depth_tolerance"):
        PhotoSettings(depth_tolerance=-1)
    with pytest.raises(PhotoSettingsError, match=r"unknown setting\(s\) \['fil'\]"):
        PhotoSettings.from_mapping({"fil": "telea"})
    assert PhotoSettings.from_mapping({"fill": "telea"}).fill == "telea"
    with pytest.raises(PhotoSettingsError, match="needs the generator's picture"):
        scene = _scene([CAR])
        render_photo(torch.zeros(3, *INPUT_SIZE[::-1]), FRAME, scene, apply_edits(scene, [Delete(12001)]),
                     settings=PhotoSettings(fill="generator"))


def test_uint8_input_stays_uint8_and_untouched_pixels_exact():
    scene = _scene([CAR, FAR_CAR])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    original = torch.from_numpy((image.permute(1, 2, 0).numpy() * 255).round().astype(np.uint8)).permute(2, 0, 1)
    result = render_photo(original, FRAME, scene, apply_edits(scene, [Rotate(12002, 0.5)]))
    assert result.image.dtype == torch.uint8 and result.image.shape == original.shape
    keep = result.source == INPUT
    assert torch.equal(result.image[:, keep], original[:, keep]) and bool((~keep).any())


def test_2d_baseline_pastes_the_objects_own_pixels_shifted():
    from sdn3d.data.edit_benchmark import BenchmarkOperation
    from sdn3d.evaluation.baselines import baseline_photo

    scene = _scene([CAR])
    K_work = K_WORK.matrix(dtype=torch.float64)
    image, covered = _surface_colors(scene, WORK[::-1], K_work)
    ids = compose_instances(scene)
    ys, xs = (ids == 12001).nonzero(as_tuple=True)
    centre = (float(xs.float().mean()), float(ys.float().mean()))
    shift = (-20.0, 3.0)
    op = BenchmarkOperation.modify(centre, (centre[0] + shift[0], centre[1] + shift[1]), 1.0, 0.0)
    out = baseline_photo(image, scene, [op], "2d", frame_size=None, settings=NO_LIGHT)
    region = ids == 12001
    moved = torch.zeros_like(region)
    moved[3:, :-20] = region[:-3, 20:]  # the region shifted by (-20, +3)
    inner = torch.nn.functional.max_pool2d((~moved)[None, None].float(), 3, 1, 1)[0, 0] == 0
    assert bool(inner.any())
    src = image[:, :-3, 20:][:, inner[3:, :-20]]
    torch.testing.assert_close(out[:, inner], src, atol=1e-5, rtol=0)  # its own pixels, moved
    squeezed = baseline_photo(image, scene, [BenchmarkOperation.modify(centre, centre, 1.0, 1.0)], "2d+",
                              frame_size=None, settings=NO_LIGHT)
    width = lambda picture: int(((picture - BACKGROUND).abs().amax(0) > 0.02).any(0).sum())  # noqa: E731
    assert width(squeezed) < 0.7 * width(image)  # 2D+ squeezes the car about its vertical axis by |cos ry|


def test_carved_silhouette_keeps_a_too_long_template_inside_the_car():
    """A template longer than the car it was fitted to overhangs the car's mask in the input; ``silhouette='carved'``
    draws none of the points the mask (or the mirrored mask) rules out, so the moved car keeps its own outline."""
    true = SceneObject(12001, template_id=0, dims=(3.2, 1.5, 1.8), ry=0.4, location=(-1.0, 1.6, 12.0))
    truth = _scene([true])
    K = _k_input()
    image, _ = _surface_colors(truth, INPUT_SIZE[::-1], K)
    fitted = truth.objects.replace(dims=torch.tensor([[4.4, 1.5, 1.8]], dtype=truth.objects.dims.dtype))
    scene = truth.replace(objects=fitted)  # the masks stay the true car's
    ops = [Move(12001, (50.0, 40.0))]
    _, car_after = _surface_colors(apply_edits(truth, ops), INPUT_SIZE[::-1], K)
    near_car = torch.nn.functional.max_pool2d(car_after[None, None].float(), 5, 1, 2)[0, 0] > 0
    outside = {}
    for mode in ("template", "carved"):
        settings = dataclasses.replace(NO_LIGHT, silhouette=mode)
        result = render_photo(image, FRAME, scene, apply_edits(scene, ops), settings=settings)
        drawn = torch.isin(result.source, torch.tensor([PHOTO, MIRROR, FALLBACK], dtype=result.source.dtype))
        outside[mode] = int((drawn & ~near_car).sum())
        assert int((drawn & car_after).sum()) > 0.8 * int(car_after.sum())  # the car itself is still drawn
    assert outside["template"] > 150 and outside["carved"] < 0.1 * outside["template"]
    with pytest.raises(PhotoSettingsError, match="silhouette"):
        PhotoSettings(silhouette="mask")


def test_the_moved_mask_adds_what_a_too_short_template_misses_when_the_view_hardly_changes():
    """A template shorter than its car misses part of it; with ``mask_view_deg`` a car moved nearer along its line of
    sight (its view unchanged) also covers its mask moved by the box's 2D map, sampled from the input's pixels."""
    true = SceneObject(12001, template_id=0, dims=(4.4, 1.5, 1.8), ry=0.4, location=(-1.0, 1.6, 14.0))
    truth = _scene([true])
    K = _k_input()
    image, _ = _surface_colors(truth, INPUT_SIZE[::-1], K)
    fitted = truth.objects.replace(dims=torch.tensor([[3.2, 1.5, 1.8]], dtype=truth.objects.dims.dtype))
    scene = truth.replace(objects=fitted)
    nearer = truth.objects.location[0] * (10.0 / 14.0)  # the same line of sight, the same yaw: the same view
    def moved(s: SceneCode) -> SceneCode:
        return s.replace(objects=s.objects.replace(location=nearer[None].to(s.objects.location.dtype)))
    expected, car_after = _surface_colors(moved(truth), INPUT_SIZE[::-1], K)
    covered = {}
    for view_deg in (0.0, 10.0):
        settings = dataclasses.replace(NO_LIGHT, silhouette="carved", mask_view_deg=view_deg)
        result = render_photo(image, FRAME, scene, moved(scene), settings=settings)
        drawn = torch.isin(result.source, torch.tensor([PHOTO, MIRROR, FALLBACK], dtype=result.source.dtype))
        covered[view_deg] = float((drawn & car_after).sum() / car_after.sum())
        if view_deg:
            assert result.objects[12001]["mask"] > 0.1
            inner = torch.nn.functional.max_pool2d((~car_after)[None, None].float(), 5, 1, 2)[0, 0] == 0
            added = inner & drawn
            assert float((result.image - expected).abs().amax(0)[added].mean()) < 0.05
    assert covered[0.0] < 0.85 and covered[10.0] > 0.95


def _zoomed_pair(z: float, zoom: float, length: float) -> tuple:
    """``(image, truth scene, fitted scene of the given template length, move, truth at its new place, its pixels)``:
    a car at depth ``z`` brought ``zoom`` times nearer along its line of sight (its view unchanged)."""
    true = SceneObject(12001, template_id=0, dims=(4.4, 1.5, 1.8), ry=0.4, location=(-1.0, 1.6, z))
    truth = _scene([true])
    image, _ = _surface_colors(truth, INPUT_SIZE[::-1], _k_input())
    fitted = truth.replace(objects=truth.objects.replace(
        dims=torch.tensor([[length, 1.5, 1.8]], dtype=truth.objects.dims.dtype)))
    nearer = truth.objects.location[0] / zoom

    def moved(s: SceneCode) -> SceneCode:
        return s.replace(objects=s.objects.replace(location=nearer[None].to(s.objects.location.dtype)))
    expected, car_after = _surface_colors(moved(truth), INPUT_SIZE[::-1], _k_input())
    return image, truth, fitted, moved, expected, car_after


def test_the_moved_mask_keeps_a_smooth_outline_when_enlarged():
    """The mask is made at the working size (half the input's here); enlarged 2.5 times by a zoom, a nearest sample of
    it drew the car's outline as a staircase of 5-pixel steps (12.5 % of the car's pixels off its true outline in
    this scene). Sampled bilinearly where it covers half, the outline follows the car's."""
    image, _, fitted, moved, _, car_after = _zoomed_pair(30.0, 2.5, 3.2)
    settings = dataclasses.replace(NO_LIGHT, silhouette="carved", mask_view_deg=10.0)
    result = render_photo(image, FRAME, fitted, moved(fitted), settings=settings)
    assert result.objects[12001]["mask"] > 0.1
    off = int(((result.source == PHOTO) ^ car_after).sum())
    assert off < 0.117 * int(car_after.sum())


def test_the_mask_is_pasted_only_where_the_fitted_outline_disagrees_with_it():
    """``paste_max_iou``: the exact template's outline matches its mask (IoU about 0.94) and its 3D transfer draws the
    zoom; a template 1.2 m too short (IoU about 0.75) is helped by its mask's pixels."""
    image, truth, fitted, moved, _, _ = _zoomed_pair(14.0, 1.4, 3.2)
    settings = dataclasses.replace(NO_LIGHT, silhouette="carved", mask_view_deg=10.0, paste_max_iou=0.9)
    exact = render_photo(image, FRAME, truth, moved(truth), settings=settings).objects[12001]
    short = render_photo(image, FRAME, fitted, moved(fitted), settings=settings).objects[12001]
    assert exact["outline_iou"] > 0.9 > short["outline_iou"] > 0.6
    assert "mask" not in exact and short["mask"] > 0.5
    always = render_photo(image, FRAME, truth, moved(truth),
                          settings=dataclasses.replace(settings, paste_max_iou=1.0)).objects[12001]
    assert always["mask"] > 0.5
    with pytest.raises(PhotoSettingsError, match="paste_max_iou"):
        PhotoSettings(paste_max_iou=1.5)


def test_a_side_seen_edge_on_stays_the_photos_when_the_edit_keeps_the_view():
    """``view_stretch``: a side the input saw nearly edge-on is taken from the input where the edit shows it no more
    squarely (a small move), and still not where a turn makes it face the camera."""
    behind = SceneObject(12001, template_id=0, dims=(4.0, 1.5, 1.8), ry=-math.pi / 2 + 0.12,
                         location=(-2.0, 1.6, 12.0))
    scene = _scene([behind])
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    nudged = scene.replace(objects=scene.objects.replace(
        location=scene.objects.location + torch.tensor([[0.0, 0.0, 0.3]], dtype=scene.objects.location.dtype)))
    strict = dataclasses.replace(NO_LIGHT, view_stretch=0.0)
    loose = dataclasses.replace(NO_LIGHT, view_stretch=1.5)
    results = {name: render_photo(image, FRAME, scene, nudged, settings=s) for name, s in (("strict", strict),
                                                                                         ("loose", loose))}
    kept = {name: r.objects[12001] for name, r in results.items()}
    assert kept["loose"]["photo"] > kept["strict"]["photo"] + 0.02
    # The pixels it now takes from the input are the right ones: the surface point's own colour.
    expected, covered = _surface_colors(nudged, INPUT_SIZE[::-1], _k_input())
    inner = torch.nn.functional.max_pool2d((~covered)[None, None].float(), 5, 1, 2)[0, 0] == 0
    gained = (results["loose"].source == PHOTO) & (results["strict"].source != PHOTO) & inner
    assert int(gained.sum()) > 10
    assert float((results["loose"].image - expected).abs().amax(0)[gained].mean()) < 0.05
    turned = apply_edits(scene, [Rotate(12001, math.pi / 2)])
    turned_px = {name: render_photo(image, FRAME, scene, turned, settings=s).source for name, s in
                 (("strict", strict), ("loose", loose))}
    # The edge-on side now faces the camera: it is not stretched over the turned car, with or without the setting.
    photo = {name: int(((src == PHOTO) | (src == MIRROR)).sum()) for name, src in turned_px.items()}
    assert abs(photo["loose"] - photo["strict"]) <= 0.02 * int((turned_px["strict"] != INPUT).sum())


def test_amodal_seen_leaves_the_flat_part_of_a_freed_car_to_the_fill():
    """Deleting a near car frees part of the car behind it; ``amodal='all'`` draws every freed point, those the photo
    never showed in flat colour; ``'seen'`` draws only what the photo or its mirror image showed and leaves the rest to
    the fill (code ``fill``)."""
    near = SceneObject(12003, template_id=2, dims=(4.0, 1.5, 1.8), ry=0.0, location=(-1.0, 1.6, 8.0))
    far = SceneObject(12004, template_id=0, dims=(4.0, 1.5, 1.8), ry=0.3, location=(-5.0, 1.6, 16.0))
    scene = _scene([near, far])  # the far car shows beside the near one (a car never shown is not completed)
    image, _ = _surface_colors(scene, INPUT_SIZE[::-1], _k_input())
    edited = apply_edits(scene, [Delete(12003)])
    codes = {}
    for mode in ("all", "seen"):
        result = render_photo(image, FRAME, scene, edited, settings=dataclasses.replace(NO_LIGHT, amodal=mode))
        codes[mode] = result.source
    flat_all = codes["all"] == FALLBACK
    assert int(flat_all.sum()) > 20  # the freed part of the far car the photo never showed
    assert not bool((codes["seen"] == FALLBACK).any())
    assert bool((codes["seen"][flat_all] == FILL).all())
    seen_all = (codes["all"] == PHOTO) | (codes["all"] == MIRROR)
    assert torch.equal(codes["seen"][seen_all], codes["all"][seen_all])  # what the photo showed is drawn either way
    with pytest.raises(PhotoSettingsError, match="amodal"):
        PhotoSettings(amodal="none")
