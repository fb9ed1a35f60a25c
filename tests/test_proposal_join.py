"""One car cut into two predicted proposals is joined where the parts' fitted cars share the ground (issues 40 and
41; :func:`sdn3d.proposal_fit.footprint_joins`): two real cars cannot stand on the same ground, so two touching
proposals whose fitted footprints overlap are one car, joined and fitted once more; two cars one behind the other
keep their own proposals, and ground-truth masks (an oracle) are never joined."""

from __future__ import annotations

import math

import pytest
import torch
from helpers.tiny_models import write_checkpoints
from test_box_objects import HEIGHT, WORK, _picture, _render

import sdn3d.derender as D
from sdn3d.derender import GroundTruth, derender
from sdn3d.geometric.fit import FitSettings
from sdn3d.labels import VKITTI_CLASS_INDEX
from sdn3d.models import Models
from sdn3d.proposal_fit import ProposalFit

CAR, ROAD = VKITTI_CLASS_INDEX["Car"], VKITTI_CLASS_INDEX["Road"]


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    ckpts = write_checkpoints(tmp_path_factory.mktemp("ckpt"))
    return Models.from_checkpoints(geometric=ckpts["geometric"], crop_size=32)


@pytest.fixture
def as_predicted(monkeypatch):
    """The frame's maps as if the semantic branch had drawn them (the join is for predicted proposals only)."""
    real = D._semantics_and_instances
    monkeypatch.setattr(D, "_semantics_and_instances", lambda *a: (*real(*a)[:2], "semantic", "branch", None))


def _cut_at_middle(mask: torch.Tensor) -> torch.Tensor:
    """``(H, W)`` instance map of one car's ``mask (H, W)`` cut at its middle column into two proposals (ids
    ``CAR*1000 + 1`` left, ``+ 2`` right; 0 elsewhere)."""
    cols = mask.any(0).nonzero().flatten()
    cut = int(cols.min() + (cols.max() - cols.min()) // 2)
    instances = torch.zeros(mask.shape, dtype=torch.long)
    instances[mask] = CAR * 1000 + 1
    right = mask.clone()
    right[:, :cut] = False
    instances[right] = CAR * 1000 + 2
    return instances


def _cut_car() -> tuple[torch.Tensor, GroundTruth, torch.Tensor]:
    """One dark car 8 m ahead, seen from its side, its mask cut at its middle column into two proposals (as two
    centre-heatmap peaks cut a near car): ``(image, maps, whole mask)``."""
    ids, masks = _render([0], [(4.2, 1.5, 1.8)], [-1.3], [(0.5, HEIGHT, 8.0)])
    instances = _cut_at_middle(masks[0])
    semantic = torch.full(ids.shape, ROAD, dtype=torch.long)
    semantic[instances > 0] = CAR
    return _picture(masks, [(0.2, 0.2, 0.25)]), GroundTruth("cut", "vkitti", semantic, instances), masks[0]


def test_footprints_are_the_boxes_bottoms_and_overlap_as_polygons():
    from sdn3d.math3d.transforms import convex_overlap, ground_footprints

    feet = ground_footprints(torch.tensor([[4.0, 1.5, 2.0], [2.0, 1.5, 2.0]]), torch.tensor([0.0, math.pi / 4]),
                             torch.tensor([[0.0, 1.65, 10.0], [0.0, 1.65, 10.0]]))
    assert feet.shape == (2, 4, 2)
    assert convex_overlap(feet[0], feet[0]) == pytest.approx(8.0)
    # a 2 m square turned 45 degrees inside a 4 x 2 m box on the same centre: its corners stick out on two sides
    assert convex_overlap(feet[0], feet[1]) == pytest.approx(convex_overlap(feet[1], feet[0]))
    assert convex_overlap(feet[0], feet[1]) == pytest.approx(4.0 - 2 * (math.sqrt(2) - 1) ** 2)
    assert convex_overlap(feet[0], feet[0] + torch.tensor([5.0, 0.0], dtype=torch.float64)) == 0.0


def _two_touching(shift_z: float) -> tuple[torch.Tensor, torch.Tensor, tuple[torch.Tensor, ...]]:
    masks = torch.zeros(2, 8, 12, dtype=torch.bool)
    masks[0, 2:6, 1:6] = True  # 20 px
    masks[1, 2:6, 6:9] = True  # 12 px, touching the first one's right edge
    geometry = (torch.tensor([0, 0]), torch.tensor([[4.0, 1.5, 1.8]] * 2, dtype=torch.float64),
                torch.zeros(2, dtype=torch.float64),
                torch.tensor([[0.0, 1.65, 10.0], [1.0, 1.65, 10.0 + shift_z]], dtype=torch.float64),
                torch.zeros(2, 64, 3))
    return masks, torch.tensor([CAR * 1000 + 1, CAR * 1000 + 2]), geometry


def test_touching_proposals_whose_footprints_overlap_are_grouped_largest_first():
    from sdn3d.proposal_fit import footprint_joins, join_masks

    masks, ids, geometry = _two_touching(0.0)  # footprints 1 m apart along the car: 3/4 shared
    fits = [ProposalFit(int(i), 0.9, False, "prediction") for i in ids]
    groups = footprint_joins(masks, ids, geometry, fits, 0.45)
    assert [g.tolist() for g in groups] == [[0, 1]]
    assert footprint_joins(masks, ids, geometry, fits, 0.8) == []  # 0.75 shared: under that threshold
    behind = _two_touching(5.0)[2]  # the second car 5 m further on: nothing shared
    assert footprint_joins(masks, ids, behind, fits, 0.45) == []
    apart = masks.clone()
    apart[1] = False
    apart[1, 2:6, 8:11] = True  # a column of road between them: the masks do not touch
    assert footprint_joins(apart, ids, geometry, fits, 0.45) == []
    unfitted = [fits[0], ProposalFit(int(ids[1]), None, True, None, "too small to fit")]
    assert footprint_joins(masks, ids, geometry, unfitted, 0.45) == []
    joined, kept_ids, kept = join_masks(masks, ids, groups)
    assert kept_ids.tolist() == [CAR * 1000 + 1] and kept.tolist() == [True, False]
    assert torch.equal(joined[0], masks.any(0))


def test_the_join_overlap_must_be_a_share_or_none():
    assert FitSettings(join_overlap=None).join_overlap is None
    for bad in (0, 1.5, True, "half"):
        with pytest.raises(ValueError, match="join_overlap"):
            FitSettings(join_overlap=bad)


@pytest.mark.fits
def test_one_cars_two_predicted_parts_are_joined_and_fitted_once(models, as_predicted):
    """Each half of the cut car is fitted as a whole car; their fitted footprints share 0.46 of the ground (so any
    threshold under that joins them): the scene holds one car, the union of the two masks, its record naming both."""
    image, gt, whole = _cut_car()
    scene = derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=HEIGHT, join_overlap=0.3))
    assert scene.meta["proposals"] == "semantic"
    assert scene.objects.instance_id.tolist() == [CAR * 1000 + 2]  # the larger part's id (the right half here)
    assert torch.equal(scene.objects.mask[0], whole)
    (record,) = scene.meta["fits"]
    assert record["joined_from"] == [CAR * 1000 + 2, CAR * 1000 + 1] and record["fit_iou"] > 0.85
    apart = derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=HEIGHT, join_overlap=None))
    assert len(apart.objects.instance_id) == 2 and all(not r["joined_from"] for r in apart.meta["fits"])


@pytest.mark.fits
def test_ground_truth_masks_are_never_joined(models):
    image, gt, _ = _cut_car()  # the cut as an oracle's masks: two objects stay two
    scene = derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=HEIGHT, join_overlap=0.3))
    assert len(scene.objects.instance_id) == 2


@pytest.mark.fits
def test_two_cars_one_partly_behind_the_other_keep_their_proposals(models, as_predicted):
    """A car 14 m ahead partly hidden behind one at 9 m (their masks touch) is fitted behind it (at 11.2 m with
    these random-weight branches: the occluder's pixels, ignored, leave its bottom edge unseen), their footprints
    sharing 0.24 of the smaller: under the default threshold (0.45), no join."""
    ids, masks = _render([0, 3], [(4.0, 1.5, 1.7), (4.2, 1.5, 1.8)], [-1.3, 0.4],
                         [(-1.0, HEIGHT, 9.0), (1.0, HEIGHT, 14.0)])
    grown = torch.nn.functional.max_pool2d(masks[:1, None].float(), 3, 1, 1)[0, 0] > 0
    assert (grown & masks[1]).any()  # the masks touch
    instances = torch.zeros(ids.shape, dtype=torch.long)
    for k in range(2):
        instances[masks[k]] = CAR * 1000 + k + 1
    semantic = torch.full(ids.shape, ROAD, dtype=torch.long)
    semantic[instances > 0] = CAR
    gt = GroundTruth("two", "vkitti", semantic, instances)
    image = _picture(masks, [(0.8, 0.1, 0.1), (0.1, 0.2, 0.7)])
    scene = derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=HEIGHT))
    assert sorted(scene.objects.instance_id.tolist()) == [CAR * 1000 + 1, CAR * 1000 + 2]
    assert [r["joined_from"] for r in scene.meta["fits"]] == [[], []]


def _cut_car_and_another() -> tuple[torch.Tensor, GroundTruth]:
    """The cut car of :func:`_cut_car` and a whole one 15 m ahead on its left, their masks apart: ``(image, maps)``
    (ids: the cut car's parts ``CAR*1000 + 1, + 2``, the other car ``+ 3``)."""
    ids, masks = _render([0, 2], [(4.2, 1.5, 1.8), (4.0, 1.5, 1.7)], [-1.3, 0.3],
                         [(0.5, HEIGHT, 8.0), (-5.0, HEIGHT, 15.0)])
    grown = torch.nn.functional.max_pool2d(masks[:1, None].float(), 3, 1, 1)[0, 0] > 0
    assert not (grown & masks[1]).any()  # the two cars' masks do not touch
    instances = _cut_at_middle(masks[0])
    instances[masks[1]] = CAR * 1000 + 3
    semantic = torch.full(ids.shape, ROAD, dtype=torch.long)
    semantic[instances > 0] = CAR
    return _picture(masks, [(0.2, 0.2, 0.25), (0.7, 0.7, 0.2)]), GroundTruth("cut", "vkitti", semantic, instances)


@pytest.fixture
def fitted_rows(monkeypatch):
    """The ids each :func:`~sdn3d.proposal_fit.fit_proposals` call of the de-render fits, one list per call."""
    calls = []
    real = D.fit_proposals

    def counted(intr, masks, ids, rows, *a, **k):
        calls.append(ids[rows].tolist())
        return real(intr, masks, ids, rows, *a, **k)

    monkeypatch.setattr(D, "fit_proposals", counted)
    return calls


@pytest.mark.fits
def test_a_join_fits_again_only_the_joined_car(models, as_predicted, fitted_rows, monkeypatch):
    """The join re-fits the joined car alone: the other car's fit reads nothing the join changed (its mask, its
    prediction, the pixels it is fitted without: the union of the parts covers the same pixels), so it keeps its first
    fit; and the scene is the one a full second pass gives (every object predicted and fitted again, as before)."""
    image, gt = _cut_car_and_another()
    settings = FitSettings(camera_height=HEIGHT, join_overlap=0.3)
    scene = derender(image, WORK, models, "gt", gt, fit=settings)
    assert scene.objects.instance_id.tolist() == [CAR * 1000 + 2, CAR * 1000 + 3]
    assert [sorted(c) for c in fitted_rows] == [[CAR * 1000 + 1, CAR * 1000 + 2, CAR * 1000 + 3], [CAR * 1000 + 2]]
    real = D._objects_3d
    monkeypatch.setattr(D, "_objects_3d", lambda *a, earlier=None, same=None: real(*a))  # main's full second pass
    fitted_rows.clear()
    full = derender(image, WORK, models, "gt", gt, fit=settings)
    assert [sorted(c) for c in fitted_rows] == [[CAR * 1000 + 1, CAR * 1000 + 2, CAR * 1000 + 3],
                                                [CAR * 1000 + 2, CAR * 1000 + 3]]
    assert full.meta == scene.meta
    for name in ("instance_id", "template_id", "mask", "code", "observed", "has_mask"):
        assert torch.equal(getattr(full.objects, name), getattr(scene.objects, name)), name
    for name in ("dims", "ry", "location", "phi"):  # the joined car's fit alone: the same up to float order
        torch.testing.assert_close(getattr(full.objects, name), getattr(scene.objects, name), rtol=0, atol=1e-5)
    assert torch.equal(full.objects.location[1], scene.objects.location[1])  # the other car's: its first fit's bits
    assert torch.equal(full.semantic, scene.semantic)


@pytest.mark.fits
def test_a_measured_camera_height_fits_every_object_again(models, as_predicted, fitted_rows):
    """The camera height measured from every prediction (``camera_height=None``) changes with the join's new
    prediction: every object's fit reads it, so all are fitted again."""
    image, gt = _cut_car_and_another()
    derender(image, WORK, models, "gt", gt, fit=FitSettings(camera_height=None, join_overlap=0.3))
    assert len(fitted_rows) == 2 and sorted(fitted_rows[1]) == [CAR * 1000 + 2, CAR * 1000 + 3]


@pytest.mark.fits
def test_a_fit_reads_no_ignored_pixel_outside_its_windows():
    """What a join may change of another object's fit: the pixels it is fitted without, read only in its windows
    (:func:`~sdn3d.geometric.fit.read_pixels`); ignoring every pixel outside them leaves its fit the same bits."""
    from sdn3d.geometric.fit import fit_to_masks, read_pixels
    from sdn3d.image_ops import mask_boxes

    _, masks = _render([0], [(4.2, 1.5, 1.8)], [-1.3], [(0.5, HEIGHT, 12.0)])
    boxes = mask_boxes(masks).float()
    settings = FitSettings(camera_height=HEIGHT)
    reads = read_pixels(boxes, tuple(masks.shape[1:]), settings)
    assert reads.sum() < reads[0].numel() / 4 and not (masks & ~reads).any()
    alone = fit_to_masks(masks, boxes, WORK, settings=settings)
    hidden = fit_to_masks(masks, boxes, WORK, ignore=~reads, settings=settings)
    for name in ("template", "dims", "ry", "location", "phi", "iou", "loss"):
        assert torch.equal(getattr(alone, name), getattr(hidden, name)), name
    edge = reads.clone()
    edge[0, :, reads[0].any(0).nonzero().min()] = False  # the ring's first column: read by the crops' samples
    assert not torch.equal(fit_to_masks(masks, boxes, WORK, ignore=~edge, settings=settings).loss, alone.loss)
