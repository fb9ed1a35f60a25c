"""Instance proposals (centre / offset targets, grouping), panoptic quality, augmentation, colours."""

from __future__ import annotations

import pytest
import torch

from sdn3d.labels import IGNORE_INDEX, class_list, thing_class_ids
from sdn3d.semantic import (
    center_focal_loss,
    center_heatmap,
    crop_size_for,
    find_centers,
    group_instances,
    panoptic_targets,
    pq_from_stats,
    pq_stats,
    random_crop_flip,
    thing_label,
    thing_mask,
)
from sdn3d.semantic.predict import SemanticPredictor
from sdn3d.visualize import colorize_labels

CAR, VAN, ROAD = 12, 13, 5
THINGS = [CAR, VAN]


def _scene() -> tuple[torch.Tensor, torch.Tensor]:
    """Two images: rectangles of Car / Van instances on road, one non-thing instance id."""
    inst = torch.zeros(2, 40, 64, dtype=torch.long)
    inst[0, 5:15, 4:20] = CAR * 1000 + 1
    inst[0, 20:32, 30:52] = VAN * 1000 + 2
    inst[0, 20:32, 52:60] = CAR * 1000 + 3  # touches the van
    inst[1, 0:10, 0:12] = CAR * 1000 + 7
    inst[1, 30:40, 50:64] = ROAD * 1000 + 9  # an id of a non-thing class: ignored
    label = torch.full((2, 40, 64), ROAD)
    cls = inst // 1000
    label[(cls == CAR) | (cls == VAN)] = cls[(cls == CAR) | (cls == VAN)]
    return inst, label


def test_thing_mask_and_class_helpers():
    inst, _ = _scene()
    mask = thing_mask(inst, THINGS)
    assert mask.sum() == 10 * 16 + 12 * 22 + 12 * 8 + 10 * 12
    vk = class_list("vkitti")
    assert thing_class_ids(vk) == THINGS and thing_class_ids(vk, ["Van"]) == [VAN]
    assert len(class_list("cityscapes")) == 19
    with pytest.raises(ValueError, match="classes"):
        class_list("kitti360")
    with pytest.raises(ValueError, match="Bus"):
        thing_class_ids(vk, ["Bus"])
    with pytest.raises(ValueError, match="integer"):
        thing_mask(inst.float(), THINGS)


def test_targets_point_every_pixel_at_its_centre_of_mass():
    inst, _ = _scene()
    t = panoptic_targets(inst, THINGS, sigma=2.0)
    mask = t.offset_mask[:, 0]
    v, u = torch.meshgrid(torch.arange(40.0), torch.arange(64.0), indexing="ij")
    pointed = torch.stack([u + t.offset[:, 0], v + t.offset[:, 1]], dim=1)  # (B, 2, H, W)
    for b, iid, centre in ((0, CAR * 1000 + 1, (11.5, 9.5)), (0, VAN * 1000 + 2, (40.5, 25.5)),
                           (1, CAR * 1000 + 7, (5.5, 4.5))):
        sel = inst[b] == iid
        torch.testing.assert_close(pointed[b, 0][sel], torch.full((int(sel.sum()),), centre[0]))
        torch.testing.assert_close(pointed[b, 1][sel], torch.full((int(sel.sum()),), centre[1]))
    assert not mask[1, 30:, 50:].any() and (t.offset[:, :, ~mask.any(0)] == 0).all()
    # One unit peak per instance, at the rounded centre; 4 instances -> 4 peaks.
    assert t.center.shape == (2, 1, 40, 64) and t.center.max() == 1.0
    assert int((t.center == 1.0).sum()) == 4
    assert t.center[0, 0, 10, 12] == 1.0  # (11.5, 9.5) rounds half to even -> (12, 10)


def test_center_heatmap_is_max_of_gaussians_and_clipped():
    centers = torch.tensor([[3.0, 3.0], [5.0, 3.0], [0.0, 0.0]])
    heat = center_heatmap(centers, torch.tensor([0, 0, 1]), (2, 8, 10), sigma=1.0)
    g = torch.exp(torch.tensor(-0.5))
    assert heat[0, 0, 3, 4] == pytest.approx(float(g))  # 1 px from both: max, not sum
    assert heat[0, 0, 3, 3] == 1.0 and heat[1, 0, 0, 0] == 1.0 and heat[1, 0, 4, 4] == 0  # 3-sigma window
    with pytest.raises(ValueError, match="sigma"):
        center_heatmap(centers, torch.zeros(3, dtype=torch.long), (1, 8, 10), sigma=0)


def test_center_focal_loss_rewards_the_target_heatmap():
    inst, _ = _scene()
    target = panoptic_targets(inst, THINGS, sigma=2.0).center
    good = torch.where(target >= 1, 9.0, -9.0)  # sure at the peaks, nothing elsewhere
    prior = torch.full_like(target, torch.logit(torch.tensor(0.01)).item())
    assert center_focal_loss(good, target) < 1e-3 < center_focal_loss(prior, target)
    # Near a peak, negatives are penalised less (penalty reduction (1 - t)^4): a false peak next to the
    # true one costs less than the same false peak far away.
    near, far = prior.clone(), prior.clone()
    near[0, 0, 10, 13], far[0, 0, 38, 2] = 3.0, 3.0
    assert center_focal_loss(near, target) < center_focal_loss(far, target)
    with pytest.raises(ValueError, match="one shape"):
        center_focal_loss(good[:, :, :5], target)


def test_find_centers_suppresses_non_maxima():
    heat = torch.zeros(1, 1, 20, 20)
    heat[0, 0, 5, 5], heat[0, 0, 6, 6], heat[0, 0, 15, 12], heat[0, 0, 1, 18] = 0.9, 0.8, 0.7, 0.05
    uv, scores, valid = find_centers(heat, threshold=0.1, nms_kernel=5, top_k=4)
    assert valid[0].tolist() == [True, True, False, False]
    assert uv[0, :2].tolist() == [[5.0, 5.0], [12.0, 15.0]] and scores[0, 0] == pytest.approx(0.9)
    with pytest.raises(ValueError, match="odd"):
        find_centers(heat, nms_kernel=4)


def test_grouping_recovers_instances_from_perfect_predictions():
    inst, label = _scene()
    t = panoptic_targets(inst, THINGS, sigma=2.0)
    pred, new_label = group_instances(label, t.center, t.offset, THINGS, threshold=0.5, nms_kernel=3)
    gt = torch.where(thing_mask(inst, THINGS), inst, 0)
    # Same partition of the pixels (ids are renumbered by centre score), class kept in the id.
    for b in range(2):
        pairs = torch.unique(torch.stack([gt[b].flatten(), pred[b].flatten()]), dim=1)
        assert pairs.shape[1] == torch.unique(gt[b]).numel()
        assert ((pairs[0] // 1000) == (pairs[1] // 1000)).all()
    torch.testing.assert_close(new_label, label)
    stats = pq_stats(pred, gt, label, THINGS)
    assert pq_from_stats(stats)["pq"].tolist() == [1.0, 1.0]


def test_grouping_majority_class_area_filter_and_no_centres():
    label = torch.full((1, 20, 20), ROAD)
    label[0, 2:12, 2:12] = CAR
    label[0, 2:5, 2:12] = VAN  # 30 van pixels, 70 car pixels in one instance
    label[0, 15:17, 15:17] = CAR  # a 4-pixel speck far from every centre
    center = torch.zeros(1, 1, 20, 20)
    center[0, 0, 7, 7] = 1.0
    offset = torch.zeros(1, 2, 20, 20)
    inst, new_label = group_instances(label, center, offset, THINGS, min_area=5)
    assert (inst[0, 2:12, 2:12] == CAR * 1000 + 1).all() and (new_label[0, 2:12, 2:12] == CAR).all()
    # The speck joins the only centre (nearest), so the instance is kept; with min_area above its size
    # a lone speck is dropped.
    lone = torch.full((1, 20, 20), ROAD)
    lone[0, 15:17, 15:17] = CAR
    center2 = torch.zeros(1, 1, 20, 20)
    center2[0, 0, 15, 15] = 1.0
    assert (group_instances(lone, center2, offset, THINGS, min_area=5)[0] == 0).all()
    assert (group_instances(label, torch.zeros_like(center), offset, THINGS)[0] == 0).all()


def test_thing_label_counts_the_vehicle_classes_together():
    """A pixel whose Car and Van together outweigh thing_odds times the best stuff class is a vehicle, although
    the arg-max (probability split between Car and Van) calls it road."""
    probability = torch.zeros(1, 14, 1, 4)
    probability[0, [CAR, VAN, ROAD], 0, 0] = torch.tensor([0.30, 0.25, 0.45])  # arg-max road; vehicles 0.55
    probability[0, [CAR, VAN, ROAD], 0, 1] = torch.tensor([0.10, 0.20, 0.70])  # vehicles 0.30 < 0.6 * 0.70
    probability[0, [CAR, ROAD], 0, 2] = torch.tensor([0.30, 0.70])  # vehicles 0.30 < 0.6 * 0.70: road
    probability[0, [VAN, ROAD], 0, 3] = torch.tensor([0.60, 0.40])  # arg-max van stays van
    assert thing_label(probability, THINGS, None)[0, 0].tolist() == [ROAD, ROAD, ROAD, VAN]
    assert thing_label(probability, THINGS, 0.6)[0, 0].tolist() == [CAR, ROAD, ROAD, VAN]
    assert thing_label(probability, THINGS, 0.4)[0, 0].tolist() == [CAR, VAN, CAR, VAN]
    with pytest.raises(ValueError, match="thing_odds"):
        thing_label(probability, THINGS, 0.0)
    with pytest.raises(ValueError, match="thing_classes"):
        thing_label(probability, [CAR, 20], 0.6)


def _two_cars_one_centre(gap: float) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """A car (columns 4-19) partly hidden behind another (20-39), one heatmap peak on the front car: the hidden car's
    offsets point at its own centre, ``gap`` px left of the front car's (votes with a 1 px spread)."""
    label = torch.full((1, 12, 44), ROAD)
    label[0, 2:10, 4:40] = CAR
    center = torch.zeros(1, 1, 12, 44)
    center[0, 0, 6, 30] = 0.9
    v, u = torch.meshgrid(torch.arange(12.0), torch.arange(44.0), indexing="ij")
    jitter = torch.sin(u * 1.7 + v * 0.9)  # a deterministic spread of about 0.7 px
    goal_u = torch.where(u < 20, 30.0 - gap, 30.0) + jitter
    offset = torch.stack([goal_u - u, 6.0 - v])[None]
    return label, center, offset


def test_grouping_splits_two_cars_whose_votes_part_under_one_centre():
    label, center, offset = _two_cars_one_centre(gap=8.0)
    merged, _ = group_instances(label, center, offset, THINGS, min_area=16)
    assert merged[0, 2:10, 4:40].unique().tolist() == [CAR * 1000 + 1]
    split, new_label = group_instances(label, center, offset, THINGS, min_area=16, split_separation=4.0)
    hidden, front = split[0, 2:10, 4:20], split[0, 2:10, 20:40]
    assert hidden.unique().numel() == 1 and front.unique().numel() == 1 and int(hidden[0, 0]) != int(front[0, 0])
    assert {int(hidden[0, 0]), int(front[0, 0])} == {CAR * 1000 + 1, CAR * 1000 + 1 + 50}
    assert (split[0, :2] == 0).all() and (new_label == label).all()
    # Votes a little apart (one car's spread) stay one car; a part under min_area is never split off.
    near, _ = group_instances(*_two_cars_one_centre(gap=1.0), THINGS, min_area=16, split_separation=4.0)
    assert near[0, 2:10, 4:40].unique().tolist() == [CAR * 1000 + 1]
    small, _ = group_instances(label, center, offset, THINGS, min_area=16 * 8 + 1, split_separation=4.0)
    assert small[0, 2:10, 4:40].unique().tolist() == [CAR * 1000 + 1]
    with pytest.raises(ValueError, match="split_separation"):
        group_instances(label, center, offset, THINGS, split_separation=0.0)


def test_grouping_counts_min_area_on_the_sure_pixels():
    """Pixels outside ``sure`` (those only thing_odds called things) join an instance but cannot make one."""
    label = torch.full((1, 10, 30), ROAD)
    label[0, 2:8, 2:12] = CAR  # 60 pixels, 20 of them sure
    label[0, 2:8, 18:28] = CAR  # 60 pixels, none sure
    sure = torch.zeros(1, 10, 30, dtype=torch.bool)
    sure[0, 2:4, 2:12] = True
    center = torch.zeros(1, 1, 10, 30)
    center[0, 0, 5, 7], center[0, 0, 5, 23] = 0.9, 0.8
    offset = torch.zeros(1, 2, 10, 30)
    v, u = torch.meshgrid(torch.arange(10.0), torch.arange(30.0), indexing="ij")
    offset[0, 0], offset[0, 1] = torch.where(u < 15, 7.0, 23.0) - u, 5.0 - v
    inst, _ = group_instances(label, center, offset, THINGS, min_area=16, sure=sure)
    assert (inst[0, 2:8, 2:12] == CAR * 1000 + 1).all() and (inst[0, :, 15:] == 0).all()
    assert (group_instances(label, center, offset, THINGS, min_area=16)[0][0, 2:8, 18:28] == CAR * 1000 + 2).all()
    with pytest.raises(ValueError, match="sure"):
        group_instances(label, center, offset, THINGS, sure=sure.long())


def test_grouping_keeps_one_car_whose_votes_spread_evenly_along_it():
    """Offsets that all point nowhere (votes = the pixels themselves, spread evenly over 40 columns): 2-means
    separates such a spread by 2 sqrt(3) standard deviations, under the threshold, so the car stays whole."""
    label = torch.full((1, 10, 48), ROAD)
    label[0, 3:7, 4:44] = CAR
    center = torch.zeros(1, 1, 10, 48)
    center[0, 0, 5, 24] = 0.9
    inst, _ = group_instances(label, center, torch.zeros(1, 2, 10, 48), THINGS, min_area=16, split_separation=4.0)
    assert inst[0, 3:7, 4:44].unique().tolist() == [CAR * 1000 + 1]


def _votes_at(goal_u: torch.Tensor, goal_v: torch.Tensor, spread: float) -> torch.Tensor:
    """``(1, 2, H, W)`` offsets whose votes land at ``(goal_u, goal_v)`` ``(H, W)`` plus a deterministic jitter of
    about ``spread`` px."""
    v, u = torch.meshgrid(torch.arange(float(goal_u.shape[0])), torch.arange(float(goal_u.shape[1])), indexing="ij")
    return torch.stack([goal_u + spread * 1.4 * torch.sin(u * 1.7 + v * 0.9) - u,
                        goal_v + spread * 1.4 * torch.cos(u * 0.8 + v * 2.3) - v])[None]


def test_grouping_gives_a_separate_blob_that_votes_for_its_own_centre_its_own_instance():
    """The real frame's failure: one heatmap peak (on car A), and car B, one pixel column away, votes at its own
    centre; a speck far right votes at neither and is under min_area. Each spatially separate part whose votes lie
    far from the main part's leaves the instance: B becomes an instance of its own, the speck no instance's."""
    label = torch.full((1, 16, 60), ROAD)
    label[0, 4:13, 4:20] = CAR  # A: 144 px
    label[0, 4:13, 21:37] = CAR  # B: one column away
    label[0, 4:7, 50:54] = CAR  # a speck of 12 px
    center = torch.zeros(1, 1, 16, 60)
    center[0, 0, 8, 12] = 0.9
    v, u = torch.meshgrid(torch.arange(16.0), torch.arange(60.0), indexing="ij")
    goal_u = torch.where(u < 20.5, 12.0, torch.where(u < 40, 29.0, 44.0))
    offset = _votes_at(goal_u, torch.full_like(u, 8.0), 2.0)
    whole, _ = group_instances(label, center, offset, THINGS, min_area=16)
    assert whole[0][label[0] == CAR].unique().tolist() == [CAR * 1000 + 1]
    inst, new_label = group_instances(label, center, offset, THINGS, min_area=16, part_separation=4.0)
    assert (inst[0, 4:13, 4:20] == CAR * 1000 + 1).all()
    assert (inst[0, 4:13, 21:37] == CAR * 1000 + 2 * 50 + 1).all()  # after the 2K ids of centres and split parts
    assert (inst[0, 4:7, 50:54] == 0).all() and (new_label == label).all()
    # B without a centre of its own (its votes land on A's side, outside B's box) is dropped, not made an instance.
    offset_away = _votes_at(torch.where(u < 40, torch.where(u < 20.5, 12.0, 0.0), 44.0), torch.full_like(u, 8.0), 2.0)
    away, _ = group_instances(label, center, offset_away, THINGS, min_area=16, part_separation=4.0)
    assert (away[0, 4:13, 4:20] == CAR * 1000 + 1).all() and (away[0, :, 20:] == 0).all()
    with pytest.raises(ValueError, match="part_separation"):
        group_instances(label, center, offset, THINGS, part_separation=0.0)
    # The predictor's defaults (GROUPING_DEFAULTS) also drop the speck and part A from B; with the 2-means split on,
    # the split (which runs first) already parts B, with the speck, as the second part of A's centre.
    probability = torch.full((1, 14, 16, 60), 0.01)
    probability[:, ROAD], probability[:, CAR][label == CAR], probability[:, ROAD][label == CAR] = 0.87, 0.87, 0.01
    out = {"logits": probability.log(), "center": center, "offset": offset}
    predicted = SemanticPredictor(_FixedNet(out), "vkitti")(torch.zeros(1, 3, 16, 60)).instance
    assert (predicted[0, 4:13, 4:20] == CAR * 1000 + 1).all() and (predicted[0, 4:13, 21:37] == CAR * 1000 + 51).all()
    assert (predicted[0, 4:7, 50:54] == 0).all()


def test_grouping_keeps_a_car_cut_by_a_pole_whole_and_drops_a_far_speck():
    """A car cut in two by a 2-px pole: both halves vote near one centre (shrunk offsets, each half's votes 2 px off
    it, a realistic 3 px spread), so the halves stay one instance; a 12-px speck whose votes point elsewhere (not
    into its own box) leaves it and, with no centre of its own, gets no instance. (A far blob of min_area sure pixels
    whose votes cluster apart is the 2-means split's second part, as on main: the split runs first.)"""
    label = torch.full((1, 16, 64), ROAD)
    label[0, 4:13, 4:36] = CAR
    label[0, 4:13, 19:21] = ROAD  # the pole
    label[0, 1:5, 54:57] = CAR  # the speck, 12 px
    center = torch.zeros(1, 1, 16, 64)
    center[0, 0, 8, 20] = 0.9
    v, u = torch.meshgrid(torch.arange(16.0), torch.arange(64.0), indexing="ij")
    goal_u = torch.where(u < 19, 18.0, torch.where(u < 40, 22.0, 44.0))
    offset = _votes_at(goal_u, torch.where(u < 40, 8.0, 10.0), 3.0)
    inst, _ = group_instances(label, center, offset, THINGS, min_area=16, split_separation=4.0, part_separation=4.0)
    car = label[0, :, :40] == CAR
    assert (inst[0, :, :40][car] == CAR * 1000 + 1).all()
    assert (inst[0, 1:5, 54:57] == 0).all()
    as_main = group_instances(label, center, offset, THINGS, min_area=16, split_separation=4.0)[0]
    assert (as_main[0, 1:5, 54:57] == CAR * 1000 + 1).all()


def test_grouping_splits_an_instance_as_grouped_before_its_far_specks_leave():
    """The 2-means split decides on the instance as grouped, specks and all, and only then do far specks leave: a
    216-px car whose halves vote 5 px apart (1 px spread) plus two 6-px specks far right whose votes land 7 px past
    the right half's. With the specks, the votes' high cluster is wide and the split (4 SDs) keeps the car whole, as
    main's grouping does; the specks then leave. Taking the specks out first would let the split cut the car."""
    label = torch.full((1, 16, 64), ROAD)
    label[0, 4:13, 4:28] = CAR
    label[0, 1:3, 50:53] = CAR
    label[0, 12:14, 58:61] = CAR
    center = torch.zeros(1, 1, 16, 64)
    center[0, 0, 8, 16] = 0.9
    v, u = torch.meshgrid(torch.arange(16.0), torch.arange(64.0), indexing="ij")
    offset = _votes_at(torch.where(u < 16, 13.0, torch.where(u < 40, 18.0, 25.0)), torch.full_like(u, 8.0), 1.0)
    car, specks = label[0, :, :40] == CAR, label[0, :, 40:] == CAR
    as_main, _ = group_instances(label, center, offset, THINGS, min_area=16, split_separation=4.0)
    assert (as_main[0][label[0] == CAR] == CAR * 1000 + 1).all()
    without_specks, _ = group_instances(torch.where(u < 40, label, ROAD), center, offset, THINGS, min_area=16,
                                        split_separation=4.0)
    assert without_specks[0, :, :40][car].unique().tolist() == [CAR * 1000 + 1, CAR * 1000 + 51]  # the car alone
    inst, _ = group_instances(label, center, offset, THINGS, min_area=16, split_separation=4.0, part_separation=4.0)
    assert (inst[0, :, :40][car] == CAR * 1000 + 1).all() and (inst[0, :, 40:][specks] == 0).all()


class _FixedNet(torch.nn.Module):
    """A semantic network stub whose outputs are given (``SemanticPredictor`` needs ``num_classes`` and a parameter)."""

    def __init__(self, out: dict[str, torch.Tensor]) -> None:
        super().__init__()
        self.num_classes = out["logits"].shape[1]
        self.anchor = torch.nn.Parameter(torch.zeros(1))
        self.out = out

    def forward(self, image: torch.Tensor) -> dict[str, torch.Tensor]:
        return self.out


def test_predictor_proposes_whole_cars_by_default():
    """With GROUPING_DEFAULTS the predictor's proposals take the car's bottom rows, where Car and Van together
    outweigh the road, and split the hidden car from the one in front; pixels no instance takes keep the
    arg-max class. Image 1 has no centre at all: no instance, labels as the arg-max."""
    label, center, offset = _two_cars_one_centre(gap=8.0)
    probability = torch.full((2, 14, 12, 44), 0.01)
    probability[:, ROAD] = 0.87
    car = label[0] == CAR
    probability[:, CAR][:, car], probability[:, ROAD][:, car] = 0.87, 0.01
    bottom = torch.zeros_like(car)
    bottom[8:10, 4:40] = True  # the car's bottom rows: arg-max road, vehicles together 0.55
    for cls, p in ((CAR, 0.30), (VAN, 0.25), (ROAD, 0.45 - 0.11)):
        probability[:, cls][:, bottom] = p
    out = {"logits": probability.log(), "center": torch.cat([center, torch.zeros_like(center)]),
           "offset": offset.expand(2, -1, -1, -1)}
    result = SemanticPredictor(_FixedNet(out), "vkitti")(torch.zeros(2, 3, 12, 44))
    inst = result.instance[0]
    assert (inst[2:10, 4:20] == inst[2, 4]).all() and (inst[2:10, 20:40] == inst[2, 20]).all()
    assert int(inst[2, 4]) != int(inst[2, 20]) and int(inst[2, 4]) // 1000 == CAR and (inst[:2] == 0).all()
    assert (result.label[0, 2:10, 4:40] == CAR).all()
    assert (result.instance[1] == 0).all() and (result.label[1][bottom] == ROAD).all()


def _reference_pq(pred, gt, label, things):
    """Loop implementation of PQ (one image at a time) to check the batched one."""
    stats = torch.zeros(4, len(things), dtype=torch.float64)
    for b in range(gt.shape[0]):
        valid = label[b] != IGNORE_INDEX
        gts = [i for i in torch.unique(gt[b][valid]).tolist() if i > 0 and i // 1000 in things]
        prs = [i for i in torch.unique(pred[b]).tolist() if i > 0 and i // 1000 in things]
        matched_g, matched_p = set(), set()
        for g in gts:
            for p in prs:
                if g // 1000 != p // 1000:
                    continue
                gm, pm = (gt[b] == g) & valid, (pred[b] == p) & valid
                inter = (gm & pm).sum().item()
                iou = inter / ((gm | pm).sum().item())
                if iou > 0.5:
                    c = things.index(g // 1000)
                    stats[0, c] += iou
                    stats[1, c] += 1
                    matched_g.add(g)
                    matched_p.add(p)
        for g in set(gts) - matched_g:
            stats[3, things.index(g // 1000)] += 1
        for p in set(prs) - matched_p:
            pm = pred[b] == p
            crowd = (label[b] == p // 1000) & (gt[b] == 0)
            if ((~valid | crowd) & pm).sum() <= 0.5 * pm.sum():
                stats[2, things.index(p // 1000)] += 1
    return stats


def test_pq_matches_a_loop_reference_on_random_maps():
    g = torch.Generator().manual_seed(1)
    totals = []
    for _ in range(4):
        gt = torch.zeros(2, 24, 32, dtype=torch.long)
        pred = torch.zeros_like(gt)
        label = torch.full_like(gt, ROAD)
        for b in range(2):
            for k in range(5):  # random overlapping boxes (later ones occlude earlier ones); predictions are
                # the ground-truth boxes shifted by 0-5 px, some with the other class
                x0, y0, dx, dy = torch.randint(0, 24, (4,), generator=g).tolist()
                cls, flip = torch.randint(0, 2, (2,), generator=g).tolist()
                gt[b, y0 % 20:y0 % 20 + 6, x0:x0 + 8] = THINGS[cls] * 1000 + k + 1
                px, py = x0 + dx % 6, y0 % 20 + dy % 3
                pcls = THINGS[cls] if k % 2 or not flip else THINGS[1 - cls]
                pred[b, py:py + 6, px:px + 8] = pcls * 1000 + k + 1
            label[b][gt[b] > 0] = gt[b][gt[b] > 0] // 1000
        label[:, :3] = IGNORE_INDEX
        label[0, 20:, :6] = CAR  # crowd: car pixels without an instance id
        gt[label == IGNORE_INDEX] = 0
        stats = pq_stats(pred, gt, label, THINGS)
        torch.testing.assert_close(stats, _reference_pq(pred, gt, label, THINGS))
        totals.append(stats[1:].sum(1))
    assert (torch.stack(totals).sum(0) > 0).all()  # the draws did produce TPs, FPs and FNs


def test_pq_hand_examples():
    gt = torch.zeros(1, 10, 10, dtype=torch.long)
    gt[0, 0:4, 0:5] = CAR * 1000 + 1  # 20 px
    label = torch.full_like(gt, ROAD)
    label[gt > 0] = CAR
    pred = torch.zeros_like(gt)
    pred[0, 0:4, 1:5] = CAR * 1000 + 5  # 16 px inside: IoU 0.8
    pred[0, 6:9, 6:9] = VAN * 1000 + 6  # a false positive van
    stats = pq_stats(pred, gt, label, THINGS)
    assert stats[:, 0].tolist() == pytest.approx([0.8, 1, 0, 0]) and stats[:, 1].tolist() == [0, 0, 1, 0]
    out = pq_from_stats(stats)
    assert out["pq"][0] == pytest.approx(0.8) and out["rq"][1] == 0 and out["pq"][1] == 0
    # A false positive on void pixels does not count; a class with no segments at all is NaN.
    label[0, 6:9, 6:9] = IGNORE_INDEX
    stats = pq_stats(pred, gt, label, THINGS)
    assert stats[2, 1] == 0 and torch.isnan(pq_from_stats(stats)["pq"][1])
    # IoU 0.5 exactly is no match: one FP and one FN.
    half = torch.zeros_like(gt)
    half[0, 0:4, 0:5] = CAR * 1000 + 2
    half[0, 4:8, 0:5] = CAR * 1000 + 2
    label[0, 4:8, 0:5] = CAR  # crowd under half of the prediction: still an FP (not more than half)
    stats = pq_stats(half, gt, label, THINGS)
    assert stats[:, 0].tolist() == [0, 0, 1, 1]
    with pytest.raises(ValueError, match="must all be"):
        pq_stats(pred[0], gt, label, THINGS)


def test_random_crop_flip_keeps_image_and_maps_aligned():
    b, h, w = 4, 12, 20
    v, u = torch.meshgrid(torch.arange(h), torch.arange(w), indexing="ij")
    code = (v * 100 + u).expand(b, h, w)
    image = torch.stack([u.float(), v.float(), torch.zeros(h, w)]).expand(b, 3, h, w)
    torch.manual_seed(3)
    out, (m,) = random_crop_flip(image, [code], crop_size=[8, 6], hflip=True)
    assert out.shape == (b, 3, 6, 8) and m.shape == (b, 6, 8)
    torch.testing.assert_close(out[:, 0].long(), m % 100)
    torch.testing.assert_close(out[:, 1].long(), m // 100)
    steps = (m[:, :, 1:] - m[:, :, :-1]).flatten(1)
    assert ((steps == 1).all(1) | (steps == -1).all(1)).all()  # contiguous columns, maybe mirrored
    assert (m[:, 1:, :] - m[:, :-1, :] == 100).all()  # rows are never flipped
    assert crop_size_for(224, 192, 624) == (192, 224) and crop_size_for(None, 5, 7) == (5, 7)
    with pytest.raises(ValueError, match="crop_size"):
        crop_size_for([1, 2, 3], 5, 5)
    same, _ = random_crop_flip(image, [code], crop_size=None, hflip=False)
    assert same is image


def test_colorize_labels_uses_dataset_colours():
    classes = class_list("vkitti")
    label = torch.tensor([[[1, 12, IGNORE_INDEX]]])
    rgb = colorize_labels(label, classes)
    assert rgb.shape == (1, 3, 1, 3)
    torch.testing.assert_close(rgb[0, :, 0, 1] * 255, torch.tensor([255.0, 127.0, 80.0]))
    assert rgb[0, :, 0, 2].sum() == 0


def test_color_jitter_ranges_identity_and_per_sample_factors():
    from sdn3d.semantic import color_jitter

    g = torch.Generator().manual_seed(0)
    image = torch.rand(4, 3, 8, 8, generator=g)
    assert color_jitter(image, 0.0) is image
    out = color_jitter(image, 0.4, generator=torch.Generator().manual_seed(1))
    assert out.shape == image.shape and out.min() >= 0 and out.max() <= 1
    assert not torch.allclose(out, image)
    # One draw per sample: a grey image stays grey (saturation has nothing to act on), and samples differ.
    grey = torch.full((3, 3, 4, 4), 0.5)
    jittered = color_jitter(grey, 0.4, generator=torch.Generator().manual_seed(2))
    torch.testing.assert_close(jittered, jittered[:, :1].expand_as(jittered))
    assert jittered[:, 0, 0, 0].unique().numel() == 3
    with pytest.raises(ValueError, match="strength"):
        color_jitter(image, 1.0)
