"""sdn3d.evaluation.proposal_recall: which annotated objects a proposal map finds (issue 18's car recall)."""

import math

import pytest
import torch

from sdn3d.evaluation.proposal_recall import RecallCounts, match_proposals

CAR, VAN = 13, 14


def _maps(h: int = 20, w: int = 20) -> tuple[torch.Tensor, torch.Tensor]:
    return torch.zeros(1, h, w, dtype=torch.long), torch.zeros(1, h, w, dtype=torch.long)


def test_perfect_proposals_find_everything():
    pred, gt = _maps()
    gt[0, :10, :10] = CAR * 1000 + 1
    gt[0, 10:, 10:] = VAN * 1000 + 7
    pred[0, :10, :10] = CAR * 1000 + 3
    pred[0, 10:, 10:] = VAN * 1000 + 1
    s = match_proposals(pred, gt, [CAR, VAN], min_pixels=50).summary({CAR: "Car", VAN: "Van"})
    assert (s["objects"], s["recall"], s["recall_class_aware"], s["precision"]) == (2, 1.0, 1.0, 1.0)
    assert s["mean_iou_found"] == pytest.approx(1.0)
    assert s["per_class"]["Car"] == {"objects": 1, "recall": 1.0, "recall_class_aware": 1.0}


def test_iou_threshold_and_class_awareness():
    pred, gt = _maps()
    gt[0, :10, :10] = CAR * 1000 + 1          # 100 px
    pred[0, :10, :6] = VAN * 1000 + 1         # IoU 0.6, wrong class
    gt[0, 10:, :10] = CAR * 1000 + 2          # 100 px
    pred[0, 10:, :4] = CAR * 1000 + 2         # IoU 0.4: not found
    s = match_proposals(pred, gt, [CAR, VAN], min_pixels=50).summary()
    assert s["objects"] == 2
    assert s["recall"] == 0.5 and s["recall_class_aware"] == 0.0
    assert s["precision"] == 0.5
    assert s["mean_iou_found"] == pytest.approx(0.6)


def test_small_objects_are_not_evaluated_but_their_proposals_are_true():
    pred, gt = _maps()
    gt[0, :3, :3] = CAR * 1000 + 1            # 9 px, under min_pixels
    pred[0, :3, :3] = CAR * 1000 + 1
    s = match_proposals(pred, gt, [CAR], min_pixels=50).summary()
    assert s["objects"] == 0 and math.isnan(s["recall"])
    assert s["precision"] == 1.0


def test_one_proposal_finds_one_object_and_other_classes_are_ignored():
    pred, gt = _maps()
    gt[0, :10, :10] = CAR * 1000 + 1
    gt[0, :10, 10:] = CAR * 1000 + 2
    pred[0, :10, :] = CAR * 1000 + 1          # covers both: IoU 0.5 with each
    gt[0, 15:, :] = 5 * 1000 + 1              # a class that is not a thing here
    pred[0, 15:, :] = 5 * 1000 + 1
    counts = match_proposals(pred, gt, [CAR], min_pixels=50)
    assert counts.objects == {CAR: 2} and counts.found == {CAR: 1}
    assert counts.proposals == 1 and counts.true_proposals == 1


def test_no_proposals_and_counts_add_up():
    pred, gt = _maps()
    gt[0, :10, :10] = CAR * 1000 + 1
    empty = match_proposals(pred, gt, [CAR], min_pixels=50)
    assert empty.summary()["recall"] == 0.0 and math.isnan(empty.summary()["precision"])
    full = match_proposals(gt.clone(), gt, [CAR], min_pixels=50)
    total = empty + full
    assert total.frames == 2 and total.objects == {CAR: 2} and total.found == {CAR: 1}
    assert total.summary()["recall"] == 0.5 and total.summary()["precision"] == 1.0


def test_matches_a_brute_force_count_on_random_maps():
    g = torch.Generator().manual_seed(0)
    for _ in range(5):
        gt = (torch.randint(0, 4, (2, 16, 16), generator=g) + CAR * 1000) * (torch.rand(2, 16, 16, generator=g) > 0.2)
        pred = torch.where(torch.rand(2, 16, 16, generator=g) > 0.3, gt, torch.randint(0, 3, (2, 16, 16),
                                                                                        generator=g) + VAN * 1000)
        counts = match_proposals(pred, gt, [CAR, VAN], min_pixels=10)
        found = objects = 0
        for b in range(2):
            for gid in gt[b].unique().tolist():
                if gid < 1000 or int((gt[b] == gid).sum()) <= 10:
                    continue
                objects += 1
                best = max(float(((pred[b] == pid) & (gt[b] == gid)).sum()) / float(((pred[b] == pid) |
                                                                                       (gt[b] == gid)).sum())
                           for pid in pred[b].unique().tolist() if pid >= 1000)
                found += best >= 0.5  # IoU > 0.5 matches are unique, so the greedy count agrees
        assert sum(counts.objects.values()) == objects and sum(counts.found.values()) == found


def test_shape_mismatch_is_an_error():
    with pytest.raises(ValueError, match="both be"):
        match_proposals(torch.zeros(1, 4, 4, dtype=torch.long), torch.zeros(1, 4, 5, dtype=torch.long), [CAR])


def test_empty_counts_summary():
    assert RecallCounts().summary()["objects"] == 0
