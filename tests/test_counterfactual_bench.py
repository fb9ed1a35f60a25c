"""The counterfactual benchmark (issue 41 item 4, sdn3d.evaluation.counterfactual): turns and deletes of sdn3d-synth's
exact pairs scored per angle bin, per source scene and method, with paired intervals against the photo default."""

from __future__ import annotations

import importlib.util
import json
import math
from pathlib import Path

import pytest
import torch
from helpers.tiny_models import write_checkpoints

from sdn3d.cli.bench import main
from sdn3d.data import counterfactual as reader
from sdn3d.data.errors import MissingDataError
from sdn3d.data.synth import SynthConfig, generate_dataset
from sdn3d.data.synth import counterfactual as writer
from sdn3d.data.vkitti1 import read_frames
from sdn3d.errors import UserInputError
from sdn3d.evaluation import counterfactual as cf
from sdn3d.evaluation.edit_benchmark import index_records

pytestmark = pytest.mark.usefixtures("one_torch_thread")
TURNS = (0, 15, 90)


@pytest.fixture(scope="module")
def pairs_tree(tmp_path_factory: pytest.TempPathFactory) -> Path:
    cfg = SynthConfig(output_dir=str(tmp_path_factory.mktemp("cfb") / "data"), seed=3, image_size=(160, 64),
                      worlds=("0001",), variations=("clone",), frames_per_sequence=5, cars_per_frame=(6, 10),
                      edit_pairs=0, occluder_pairs=0, workers=1, threads=1, counterfactual_cars=1,
                      counterfactual_turns=TURNS)
    return generate_dataset(cfg)


def test_reader_reads_the_writers_index(pairs_tree: Path, tmp_path: Path) -> None:
    assert (reader.PAIRS_NAME, reader.PAIRS_FORMAT) == (writer.PAIRS_NAME, writer.PAIRS_FORMAT)
    index = reader.load_pairs(pairs_tree)
    assert index.image_size == (160, 64) and len(index.pairs) == len(TURNS) + 1
    assert [cf.pair_bin(p) for p in index.pairs] == ["turn 0", "turn 15", "turn 90", "delete"]
    p = index.pairs[0]
    assert reader.load_pair_mask(pairs_tree, p, "source_mask").sum() == p.pixels["source_mask"]
    assert reader.load_pair_rgb(pairs_tree, p).shape == (64, 160, 3)
    with pytest.raises(MissingDataError, match="counterfactual_cars"):
        reader.load_pairs(tmp_path)


def test_zero_turn_with_ground_truth_geometry_is_exact(pairs_tree: Path) -> None:
    index = reader.load_pairs(pairs_tree)
    settings = cf.CounterfactualSettings(fills=("auto", "telea"))
    results = cf.run_counterfactual(index, index_records(read_frames(pairs_tree)), None, settings)
    assert {r.source for r in results} == {"oracle"} and all(not r.errors for r in results)
    zero = next(r for r in results if r.bin == "turn 0")
    for method in ("photo:auto", "photo:telea", "2d", "2d+"):
        # a 0-degree turn draws the car where it was, with its own pixels: the target render bit for bit
        assert zero.metrics[method]["car"]["psnr"] == pytest.approx(60.0) and zero.metrics[method]["car"]["l1"] == 0
    assert zero.metrics["photo:auto"]["car"]["flat"] == 0
    turned = next(r for r in results if r.bin == "turn 90")
    assert turned.metrics["photo:auto"]["car"]["psnr"] < 60 and 0 <= turned.metrics["photo:auto"]["car"]["flat"] <= 1
    delete = next(r for r in results if r.kind == "delete")
    assert set(delete.metrics["photo:auto"]["hole"]) == {"psnr", "l1", "darkening", "darkening_error"}
    assert delete.reference["source"] > delete.reference["target"]  # the input still has the car's shadow
    with pytest.raises(UserInputError, match="checkpoints.geometric"):
        cf.run_counterfactual(index, {}, None, cf.CounterfactualSettings(sources=("oracle", "gt")))


def test_darkening_is_one_minus_the_band_over_the_ring() -> None:
    image = torch.full((3, 8, 8), 0.5)
    band = torch.zeros(8, 8, dtype=torch.bool)
    band[3:5, 3:5] = True
    image[:, band] = 0.25
    road = torch.ones(8, 8, dtype=torch.bool)
    ring = cf.road_ring(band, torch.zeros_like(band), road, torch.zeros_like(band), 1)
    assert ring.sum() == 16 - 4 and not (ring & band).any()
    assert cf.darkening(image, band, ring) == pytest.approx(0.5)
    assert math.isnan(cf.darkening(image, band, torch.zeros_like(band)))


def test_cli_writes_per_bin_tables_with_labelled_sources_and_paired_intervals(pairs_tree: Path, tmp_path: Path,
                                                                               capsys: pytest.CaptureFixture) -> None:
    ckpts = write_checkpoints(tmp_path / "ckpt")
    out = tmp_path / "cf"
    args = ["counterfactual=true", f"data.root={pairs_tree}", f"output_dir={out}", "counterfactual_fills=[auto]",
            f"checkpoints.geometric={ckpts['geometric']}", f"checkpoints.textural={ckpts['textural']}",
            "geometric.min_pixels=4"]
    assert main(args) == 0
    report = json.loads((out / "counterfactual.json").read_text())
    md = (out / "counterfactual.md").read_text()
    assert report["info"]["sources"] == ["oracle", "gt"]  # gt masks: the geometric branch is given
    assert report["info"]["source_labels"] == {"oracle": "oracle: ground-truth geometry",
                                               "gt": "oracle: ground-truth masks"}
    for label in report["info"]["source_labels"].values():
        assert f"## Source scene: {label}" in md
    assert report["info"]["methods"] == ["photo:auto", "generator", "2d", "2d+"]
    oracle = report["summary"]["oracle"]
    assert list(oracle) == ["turn 0", "turn 15", "turn 90", "delete"]
    assert oracle["turn 0"]["methods"]["photo:auto"]["car"]["psnr"]["mean"] == pytest.approx(60.0)
    assert oracle["delete"]["methods"]["generator"]["hole"]["psnr"]["n"] == 1
    d = report["comparisons"]["oracle"]["turn 90"]["2d"]["car.psnr"]
    assert {"mean", "low", "high", "wins", "losses", "ties", "verdict"} <= set(d) and d["n"] == 1
    assert report["outputs"] == ["counterfactual.json", "counterfactual.md"]
    assert "| turn 90 | photo:auto |" in capsys.readouterr().out
    # benchmarks/counterfactual_compare.py: two runs on the same pairs, paired per pair key (here a run with itself)
    spec = importlib.util.spec_from_file_location("cf_compare", Path(__file__).parents[1] / "benchmarks" /
                                                  "counterfactual_compare.py")
    compare = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(compare)
    rows = compare.compare(report, report, ["photo:auto"])
    assert rows and all(r["ties"] == r["n"] and r["mean"] == 0 for r in rows)
    assert {r["column"] for r in rows} >= {"car.psnr", "car.flat", "hole.psnr", "hole.darkening_error"}
    # one target car: every interval resamples it whole, and the 90-degree turns are pooled as turns >= 45
    assert {p["car"] for p in report["pairs"]} == {f"0001/{report['pairs'][0]['key'].split('_')[1].split()[0]}"}
    assert all(r["groups"] == 1 for r in rows) and {"turn >= 45", "turn 90"} <= {r["bin"] for r in rows}
    assert oracle["turn 90"]["methods"]["2d"]["car"]["psnr"]["cars"] == 1
    assert "| turn 90 | 2d | 1 (1) |" in md
    old = json.loads(json.dumps(report))
    del old["pairs"][0]["car"]
    with pytest.raises(ValueError, match="names no car"):
        compare.compare(old, report)


def _pair(car: str, frame: int, psnr: float) -> cf.PairResult:
    return cf.PairResult(f"{car.split('/')[0]}/clone/{frame:05d}_{car.split('/')[1]} turn_90", "oracle", "turn 90",
                         "turn", {"car": 100}, car, metrics={"photo:auto": {"car": {"psnr": 20.0}},
                                                             "2d": {"car": {"psnr": psnr}}})


def test_intervals_resample_whole_cars_not_pairs() -> None:
    """Twelve pairs of three parked cars are three pieces of evidence: the comparison counts the cars and gives no
    verdict (under MIN_ENTRIES cars) where a pair-level bootstrap would call a clear winner; the interval is the
    cluster bootstrap's."""
    results = [_pair(car, f, 20.0 + gain + 0.01 * f) for car, gain in (("0001/1002", 1.0), ("0001/1003", 0.2),
                                                                       ("0002/1002", 2.0)) for f in range(4)]
    d = cf.comparisons(results, ["photo:auto", "2d"])["oracle"]["turn 90"]["2d"]["car.psnr"]
    assert (d["n"], d["groups"], d["verdict"]) == (12, 3, "too few entries")
    gains = [r.metrics["2d"]["car"]["psnr"] - 20.0 for r in results]
    assert (d["low"], d["high"]) == pytest.approx((min(gains), max(gains)), abs=0.05)  # a whole car's mean at the ends
    stat = cf.summarize(results, ["photo:auto", "2d"])["oracle"]["turn 90"]["methods"]["2d"]["car"]["psnr"]
    assert (stat["n"], stat["cars"]) == (12, 3)


def test_cli_counterfactual_kinds_scores_the_deletes_alone(pairs_tree: Path, tmp_path: Path) -> None:
    out = tmp_path / "cfd"
    args = ["counterfactual=true", f"data.root={pairs_tree}", f"output_dir={out}", "counterfactual_fills=[auto,rays]",
            "counterfactual_kinds=[delete]", "counterfactual_sources=[oracle]"]
    assert main(args) == 0
    report = json.loads((out / "counterfactual.json").read_text())
    assert list(report["summary"]["oracle"]) == ["delete"] and {p["kind"] for p in report["pairs"]} == {"delete"}
    assert report["info"]["methods"][:2] == ["photo:auto", "photo:rays"]
    assert "was not scored here" not in (out / "counterfactual.md").read_text()


def test_cli_says_when_the_reference_was_not_scored(pairs_tree: Path, tmp_path: Path) -> None:
    """Without ``auto`` among the fills there is nothing to pair against: the table says so instead of leaving the
    columns of differences empty without a word."""
    out = tmp_path / "cfr"
    args = ["counterfactual=true", f"data.root={pairs_tree}", f"output_dir={out}", "counterfactual_fills=[rays]",
            "counterfactual_kinds=[delete]", "counterfactual_sources=[oracle]"]
    assert main(args) == 0
    assert "photo:auto" not in json.loads((out / "counterfactual.json").read_text())["info"]["methods"]
    assert "`photo:auto` was not scored here (`counterfactual_fills` without `auto`, or another " in (
        out / "counterfactual.md").read_text()


def test_cli_pairs_every_method_against_the_reference_it_is_given(pairs_tree: Path, tmp_path: Path,
                                                                   capsys: pytest.CaptureFixture) -> None:
    """``counterfactual_reference=2d``: every paired difference is a method minus the 2D paste (3D-SDN's delete
    against 2D's in the table itself, the comparison issue 40 asks for); a name that is no method is refused by name
    before anything is written."""
    out = tmp_path / "cf2d"
    args = ["counterfactual=true", f"data.root={pairs_tree}", f"output_dir={out}", "counterfactual_fills=[rays]",
            "counterfactual_kinds=[delete]", "counterfactual_sources=[oracle]", "counterfactual_reference=2d"]
    assert main(args) == 0
    report = json.loads((out / "counterfactual.json").read_text())
    assert report["info"]["reference"] == "2d"
    diff = report["comparisons"]["oracle"]["delete"]["photo:rays"]["hole.psnr"]
    pairs = [p for p in report["pairs"] if p["kind"] == "delete"]
    want = sum(p["metrics"]["photo:rays"]["hole"]["psnr"] - p["metrics"]["2d"]["hole"]["psnr"] for p in pairs)
    assert diff["n"] == len(pairs) and diff["mean"] == pytest.approx(want / len(pairs))
    assert "2d" not in report["comparisons"]["oracle"]["delete"]  # the reference is not paired with itself
    text = (out / "counterfactual.md").read_text()
    assert "Reference of every paired difference: `2d`." in text and "was not scored here" not in text
    bad = tmp_path / "bad"
    assert main([*args[:2], f"output_dir={bad}", "counterfactual_reference=photo:magic"]) == 2
    assert "counterfactual_reference must be one of" in capsys.readouterr().err and not bad.exists()
