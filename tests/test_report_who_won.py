"""Issue 42 items 6-7: the benchmark's headline says who won (paired intervals, win counts, the best value in bold),
the demo report explains its proposal precisions and prints each stage's time with the machine it ran on."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sdn3d.cli.bench import edited_car_groups, paired_comparisons
from sdn3d.cli.demo import machine_sentence, precision_note, stage_rows
from sdn3d.evaluation.paired import MIN_ENTRIES, compare_entries, paired_difference


def test_a_paired_difference_is_seeded_and_counts_wins_by_the_metric_direction():
    rng = np.random.default_rng(3)
    base = rng.uniform(0.1, 0.2, size=40)
    ours = base - 0.01  # L1: lower is better, ours wins every entry
    a = paired_difference(ours, base, higher_is_better=False)
    b = paired_difference(ours, base, higher_is_better=False)
    assert a == b
    assert (a.wins, a.losses, a.ties) == (40, 0, 0)
    assert a.high < 0 and a.verdict == "better"
    flipped = paired_difference(ours, base, higher_is_better=True)
    assert (flipped.wins, flipped.losses) == (0, 40) and flipped.verdict == "worse"


def test_a_gap_within_the_noise_is_no_verdict_and_few_entries_are_none():
    rng = np.random.default_rng(0)
    x = rng.normal(size=60)
    noisy = paired_difference(x + rng.normal(scale=0.01, size=60), x, higher_is_better=True)
    assert noisy.low < 0 < noisy.high and noisy.verdict == "no clear difference"
    few = paired_difference([1.0] * (MIN_ENTRIES - 1), [0.0] * (MIN_ENTRIES - 1), higher_is_better=True)
    assert few.verdict == "too few entries"
    with pytest.raises(ValueError, match="one length"):
        paired_difference([1.0, 2.0], [1.0], higher_is_better=True)


def _entry(i: int, ours: float, theirs: float | None) -> dict:
    methods = {"3d-sdn": {"all": {"psnr": ours, "l1": 0.1}}}
    if theirs is not None:
        methods["2d"] = {"all": {"psnr": theirs, "l1": 0.2}}
    return {"index": i, "metrics": {"photo": methods}}


def test_entries_without_both_methods_are_left_out_of_the_pairing():
    entries = [_entry(i, 15.0 + i % 3, 14.0) for i in range(12)] + [_entry(99, 40.0, None)]
    comp = compare_entries(entries, "photo", "3d-sdn", "2d", [("psnr", "all"), ("l1", "all")])
    assert comp[("psnr", "all")].n == 12 and math.isclose(comp[("psnr", "all")].mean, 2.0)
    assert comp[("l1", "all")].verdict == "better"  # 0.1 against 0.2, lower is better



def test_one_edit_twice_is_one_piece_of_evidence():
    """The generator can draw one occluder pair for two slots: those entries are resampled together, so the
    interval is as wide as the distinct edits allow and the verdict counts distinct edits."""
    rng = np.random.default_rng(1)
    distinct = rng.normal(0.3, 1.0, size=12)
    ours, theirs = np.repeat(distinct, 3), np.zeros(36)  # every edit three times
    groups = np.repeat(np.arange(12), 3).tolist()
    naive = paired_difference(ours, theirs, higher_is_better=True)
    grouped = paired_difference(ours, theirs, higher_is_better=True, groups=groups)
    alone = paired_difference(distinct, np.zeros(12), higher_is_better=True)
    assert grouped.n == 36 and grouped.groups == 12 and math.isclose(grouped.mean, naive.mean)
    assert grouped.high - grouped.low > 1.4 * (naive.high - naive.low)  # sqrt(3) wider, about
    assert math.isclose(grouped.high - grouped.low, alone.high - alone.low, rel_tol=0.25)
    few = paired_difference(np.repeat(distinct[:4], 3), np.zeros(12), True, groups=np.repeat(np.arange(4), 3).tolist())
    assert few.verdict == "too few entries"  # 12 entries, 4 edits
    # every label distinct: the ungrouped result, draw for draw
    same = paired_difference(distinct, np.zeros(12), True, groups=list("abcdefghijkl"))
    assert (same.low, same.high, same.groups) == (alone.low, alone.high, 12)
    with pytest.raises(ValueError, match="one label per entry"):
        paired_difference([1.0, 2.0], [1.0, 1.0], True, groups=["a"])


def test_the_bench_groups_entries_that_edit_the_same_cars():
    """Entries that edit one car (another source frame, the other variation, or one edit twice) are one group of
    the paired bootstrap; an entry naming no car is its own."""
    records = [{"index": 0, "cars": ["0001/1003"]},
               {"index": 1, "cars": ["0001/1003"]},  # the same car from another source frame or variation
               {"index": 2, "cars": ["0001/1004"]},
               {"index": 3, "cars": ["0002/1003"]},  # another world's car of the same id
               {"index": 4, "cars": []},
               {"index": 5, "cars": ["0001/1003", "0001/1004"]}]
    groups = edited_car_groups(records + [{"index": 2, "cars": []}])  # another pass that found no car keeps it
    assert groups[0] == groups[1] and len({groups[i] for i in (0, 2, 3, 4, 5)}) == 5
    entries = [_entry(i, 15.0 + i, 14.0) for i in range(4)]
    info = {"compose": ["photo"], "sources": ["gt"]}
    summaries = {"gt": _summary({"3d-sdn": [15.0, 16.0, 17.0, 18.0], "2d": [14.0] * 4})}
    grouped = paired_comparisons({"gt": entries}, summaries, info, groups=groups)["gt"]["psnr/all"]
    plain = paired_comparisons({"gt": entries}, summaries, info)["gt"]["psnr/all"]
    assert (grouped["n"], grouped["groups"], plain["groups"]) == (4, 3, None)


def _summary(values: dict[str, list[float]]) -> dict:
    stat = {m: {"all": {"psnr": {"mean": float(np.mean(v)), "n": len(v)}}} for m, v in values.items()}
    return {"evaluated": len(next(iter(values.values()))), "methods": {"photo": stat}}


def test_who_won_counts_groups_of_cars_not_entries():
    """Twelve entries that edit three cars: the sentence names both counts and calls nothing (under MIN_ENTRIES
    groups), although twelve entries would be enough."""
    from sdn3d.cli.bench import who_won_lines

    entries = [{**_entry(i, 16.0 + 0.01 * i, 14.0), "cars": [f"0001/{1002 + i % 3}"]} for i in range(12)]
    info = {"compose": ["photo"], "sources": ["gt"]}
    summaries = {"gt": _summary({"3d-sdn": [16.0] * 12, "2d": [14.0] * 12})}
    comps = paired_comparisons({"gt": entries}, summaries, info, groups=edited_car_groups(entries))
    text = "\n".join(who_won_lines(comps, summaries, info))
    assert "(12 entries, 3 groups of cars): **too few entries to call" in text
    alone = paired_comparisons({"gt": entries}, summaries, info)
    ungrouped = "\n".join(who_won_lines(alone, summaries, info))
    assert "(12 entries): **" in ungrouped and "too few entries to call" not in ungrouped


def test_the_headline_marks_the_best_row_and_says_who_won():
    n = 20
    ours, twod = [13.0 + 0.02 * i for i in range(n)], [14.0 + 0.02 * i for i in range(n)]
    entries = {"semantic": [{"index": i, "metrics": {"photo": {"3d-sdn": {"all": {"psnr": ours[i]}},
                                                               "2d": {"all": {"psnr": twod[i]}},
                                                               "2d+": {"all": {"psnr": 13.5}}}}}
                            for i in range(n)]}
    summaries = {"semantic": _summary({"3d-sdn": ours, "2d": twod, "2d+": [13.5] * n})}
    info = {"compose": ["photo"], "sources": ["semantic"], "benchmark": "bench.json"}
    comparisons = paired_comparisons(entries, summaries, info)
    assert comparisons["semantic"]["psnr/all"]["verdict"] == "worse"
    from sdn3d.cli.bench import _headline

    head = "\n".join(_headline(summaries, info, comparisons))
    assert "| predicted | 2D | n/a | n/a | n/a | n/a | n/a | n/a | **14.19** |" in head
    assert "3D-SDN is worse in 1 column," in head and "(20 entries)" in head
    assert "-1.00 [-1.00, -1.00] | 0 / 20 of 20 | worse |" in head


def test_the_demo_report_names_each_precision_and_each_stage_time():
    info = {"training": {"semantic": {"metrics": {"val/proposal_precision": 0.742, "test/proposal_precision": 0.6126},
                                      "demo_wall_s": 200.0}},
            "proposal_recall": {"precision": 0.68, "min_pixels": 256, "work_size": [312, 96]},
            "stages_s": {"data": 30.0, "train": 400.0, "bench": 60.0, "edits": 20.0}, "wall_s": 520.0,
            "threads": 2, "machine": {"processor": "Test CPU", "logical_cpus": 2, "load_average_start": [5.0, 4, 3],
                                      "load_average_end": [6.0, 5, 4]}}
    note = precision_note(info)
    assert "0.742 on the **validation** part" in note and "0.613 on the **test** part" in note
    assert "0.680 on the **test** part at the edits' 312x96" in note
    rows = stage_rows(info)
    assert "| training: semantic | 200 |" in rows and "| whole demo | 520 |" in rows
    sentence = machine_sentence(info)
    assert "Test CPU, 2 logical cores, 2 torch threads" in sentence and "busy machine" in sentence
