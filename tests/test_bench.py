"""The editing benchmark (Table 1) on the tiny synthetic dataset with random-weight branches."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
import torch
from helpers.tiny_models import TEXTURAL_HP, geometric_net, textural_spec, write_checkpoints
from PIL import Image

from sdn3d.cli.bench import main
from sdn3d.data import vkitti1
from sdn3d.data.edit_benchmark import BenchmarkEntry, load_edit_benchmark, scale_operation
from sdn3d.data.records import load_instances
from sdn3d.data.scene_gt import scene_from_frame
from sdn3d.editing.pick import projected_centers
from sdn3d.errors import UserInputError
from sdn3d.evaluation.edit_benchmark import (
    BenchSettings,
    EntryResult,
    edit_regions,
    index_records,
    mask_iou,
    region_metrics,
    run_benchmark,
    summarize,
)
from sdn3d.geometric.predict import GeometricPredictor
from sdn3d.image_ops import mask_boxes, resize_map
from sdn3d.labels import class_list
from sdn3d.models import Models
from sdn3d.nets.lpips import LPIPS
from sdn3d.nets.pix2pixhd import TexturalSpec
from sdn3d.textural.renderer import TexturalRenderer

SIZE = (160, 64)


@pytest.fixture(scope="module")
def bench(tiny_synth):
    entries = load_edit_benchmark(tiny_synth / "vkitti_edit_benchmark.json")
    return entries, index_records(vkitti1.read_frames(tiny_synth))


@pytest.fixture(scope="module")
def models() -> Models:
    torch.manual_seed(0)
    return Models(None, GeometricPredictor(geometric_net()), TexturalRenderer(textural_spec()), crop_size=32)


def _gt(record):
    return resize_map(torch.from_numpy(load_instances(record)).long(), SIZE)


def test_edit_regions_are_source_and_target_masks_of_the_picked_objects(bench):
    entries, records = bench
    entry = entries[0]
    source, target = (records[(entry.world, entry.variation, f)] for f in (entry.source_frame, entry.target_frame))
    regions, box, ids = edit_regions(entry, source, target, SIZE)
    oracle = scene_from_frame(source, SIZE)
    centres, _ = projected_centers(oracle)
    expected = []
    for op in entry.operations:
        uv = torch.tensor(scale_operation(op, (1242, 375), SIZE).from_uv, dtype=torch.float64)
        expected.append(int(oracle.objects.instance_id[(centres - uv).norm(dim=1).argmin()]))
    assert ids == expected and len(set(ids)) == len(ids)
    src, tgt = _gt(source), _gt(target)
    union = torch.zeros_like(regions)
    for iid in ids:
        union |= (src == iid) | (tgt == iid)
    assert torch.equal(regions, union) and bool(regions.any())
    areas = [int(((src == i) | (tgt == i)).sum()) for i in ids]
    largest = ids[areas.index(max(areas))]
    assert box.tolist() == mask_boxes((tgt == largest)[None])[0].tolist()


def test_region_metrics_whole_all_and_largest():
    target = torch.rand(3, 40, 60)
    regions = torch.zeros(40, 60, dtype=torch.bool)
    regions[5:10, 4:12] = True
    same = region_metrics(target, target, regions, torch.tensor([4, 5, 12, 10]))
    assert all(same[r]["l1"] == 0 for r in ("whole", "all", "largest"))
    assert same["whole"]["ssim"] == pytest.approx(1.0, abs=1e-5) and same["all"]["psnr"] == math.inf
    pred = target.clone()
    pred[:, regions] = (pred[:, regions] + 0.5) % 1  # changed only inside the edited region
    out = region_metrics(pred, target, regions, torch.tensor([4, 5, 12, 10]))
    assert out["all"]["l1"] == pytest.approx(out["largest"]["l1"])  # the box is the region here
    assert out["whole"]["l1"] == pytest.approx(out["all"]["l1"] * 40 / 2400)
    net = LPIPS().eval()
    with_lpips = region_metrics(pred, target, regions, torch.tensor([4, 5, 12, 10]), net)
    assert {"lpips", "l1", "ssim", "psnr"} == set(with_lpips["largest"]) and math.isfinite(with_lpips["all"]["lpips"])


@pytest.mark.parametrize("scene", ["derender", "oracle"])
def test_run_benchmark_evaluates_every_method(bench, models, scene):
    entries, records = bench
    settings = BenchSettings(image_size=SIZE, scene=scene, proposals="gt", min_pixels=1, examples=1)
    results = run_benchmark(entries, records, models, settings)
    assert len(results) == 1 and not results[0].errors
    r = results[0]
    assert list(r.metrics) == ["photo", "full", "edited"]
    assert all(set(v) == {"3d-sdn", "2d", "2d+"} for v in r.metrics.values())
    for per_method in r.metrics.values():
        for method in per_method.values():
            for region in ("whole", "all", "largest", "objects"):
                assert all(math.isfinite(v) for v in method[region].values()) and "lpips" not in method[region]
    assert r.latency_ms["total"] == pytest.approx(sum(r.latency_ms[k] for k in ("derender", "edit", "render")))
    assert r.latency_ms["compose"] > 0 and r.latency_ms["photo"] > 0
    pictures = {f"{c}:{m}" for c in ("photo", "full", "edited") for m in ("3d-sdn", "2d", "2d+")}
    assert set(r.images) == {"source", "target"} | pictures
    assert r.images["target"].shape == (64, 160, 3) and r.regions.any()
    for m in ("3d-sdn", "2d", "2d+"):  # edited: the source wherever the method's edit left the maps alone
        full, edited, source = (r.images[k].astype(int) for k in (f"full:{m}", f"edited:{m}", "source"))
        kept = (edited == source).all(-1)
        assert kept.any() and (~kept).any() and not (edited == full).all()
        assert r.metrics["edited"][m]["layout"] == r.metrics["full"][m]["layout"]
        photo = r.images[f"photo:{m}"].astype(int)  # photo: the source's own pixels away from the edit
        same = (photo == source).all(-1)
        assert same.mean() > 0.5 and (~same[r.regions]).any()
    iou = {m: r.metrics["full"][m]["layout"]["mask_iou"] for m in r.metrics["full"]}
    if scene == "oracle":  # true geometry: the 3D edit puts the rotated cars where the target shows them
        # (on tiny_synth's entry 0: 0.978 against 0.833 for 2D)
        assert iou["3d-sdn"] > 0.95 and iou["3d-sdn"] > iou["2d"] + 0.1 and iou["3d-sdn"] > iou["2d+"] + 0.1


def test_identity_entry_gives_the_same_image_for_every_method(bench, models):
    entries, records = bench
    e = entries[0]
    identity = BenchmarkEntry(e.world, e.variation, e.source_frame, e.source_frame, ())
    missing = BenchmarkEntry(e.world, e.variation, 90, 91, e.operations)
    settings = BenchSettings(image_size=SIZE, scene="oracle", include_identity=True, examples=1)
    results = run_benchmark([identity, missing], records, models, settings)
    same = results[0]
    full = same.metrics["full"]
    assert full["3d-sdn"]["whole"] == full["2d"]["whole"] == full["2d+"]["whole"]
    assert torch.equal(torch.from_numpy(same.images["full:3d-sdn"]), torch.from_numpy(same.images["full:2d+"]))
    assert math.isnan(full["3d-sdn"]["all"]["l1"])  # nothing edited: no region
    for m in ("3d-sdn", "2d", "2d+"):  # nothing edited: compose edited and photo give the source itself
        assert (same.images[f"edited:{m}"] == same.images["source"]).all()
        assert (same.images[f"photo:{m}"] == same.images["source"]).all()
    assert "not in the dataset" in results[1].errors["entry"]
    summary = summarize(results)
    assert summary["entries"] == 2 and summary["evaluated"] == 1 and summary["failed"]["2d"] == 1
    assert summary["compose"] == ["photo", "full", "edited"]
    stats = summary["methods"]["full"]["2d"]
    assert stats["whole"]["l1"]["n"] == 1 and stats["all"]["l1"]["n"] == 0
    with pytest.raises(ValueError, match="none of the 1 benchmark entries"):
        run_benchmark([missing], records, models, settings)


def test_mask_iou_pairs_each_methods_pick_with_the_true_object():
    """Predicted proposals number objects their own way: an operation's pick is compared with the object the
    operation meant, not with whatever ground-truth object shares its id."""
    target = torch.zeros(4, 6, dtype=torch.long)
    target[:2, :3], target[2:, 3:] = 13001, 13002
    drawn = torch.zeros_like(target)
    drawn[:2, :3] = 13007  # the semantic branch's id for the first car, drawn where the target has it
    drawn[2:, 4:] = 13001  # its id for the second car reuses the first car's ground-truth id
    assert mask_iou(drawn, target, [13007, 13001], [13001, 13002]) == pytest.approx((1 + 4 / 6) / 2)
    assert mask_iou(drawn, target, [13009], [13003]) != mask_iou(drawn, target, [13009], [13003])  # NaN: deleted
    with pytest.raises(ValueError, match="pair up"):
        mask_iou(drawn, target, [13007], [13001, 13002])


def test_summarize_averages_entries():
    def entry(i, l1):
        return EntryResult(i, f"k{i}", 1, {"full": {"3d-sdn": {"whole": {"l1": l1}, "all": {}, "largest": {}}},
                                           "edited": {"3d-sdn": {"whole": {"l1": l1 / 2}}}},
                           {"derender": 1.0, "edit": 2.0, "render": 3.0, "total": 6.0 + i, "compose": 0.5})
    summary = summarize([entry(0, 0.2), entry(1, 0.4), entry(2, float("nan"))])
    stat = summary["methods"]["full"]["3d-sdn"]["whole"]["l1"]
    assert stat["mean"] == pytest.approx(0.3) and stat["n"] == 2
    assert summary["methods"]["edited"]["3d-sdn"]["whole"]["l1"]["mean"] == pytest.approx(0.15)
    assert summary["latency_ms"]["total"]["mean"] == pytest.approx(7.0)
    assert summary["latency_ms"]["compose"]["mean"] == pytest.approx(0.5)


def _cli_args(tiny_synth, ckpts, out, *extra):
    return [f"data.root={tiny_synth}", "data.image_size=[160,64]", f"checkpoints.geometric={ckpts['geometric']}",
            f"checkpoints.textural={ckpts['textural']}", "geometric.crop_size=32", "geometric.min_pixels=1",
            f"output_dir={out}", *extra]


def test_bench_cli_writes_table_page_and_examples(tiny_synth, tmp_path, capsys):
    ckpts = write_checkpoints(tmp_path / "ckpt")
    torch.save(LPIPS().state_dict(), tmp_path / "lpips.pth")
    out = tmp_path / "bench"
    args = _cli_args(tiny_synth, ckpts, out, "proposals=gt", f"lpips_weights={tmp_path / 'lpips.pth'}")
    assert main(args) == 0
    report = json.loads((out / "results.json").read_text())
    summary = report["summary"]["gt"]
    assert summary["evaluated"] == 1 and report["info"]["lpips"] is True
    assert report["info"]["compose"] == ["photo", "full", "edited"] and report["info"]["sources"] == ["gt"]
    assert report["info"]["source_labels"] == {"gt": "oracle: ground-truth masks and semantics"}
    for compose in ("photo", "full", "edited"):
        assert math.isfinite(summary["methods"][compose]["3d-sdn"]["largest"]["lpips"]["mean"])
    table = (out / "table1.md").read_text()
    assert table.startswith("# Editing benchmark: headline")  # the headline first: photo rows, columns with values
    headline = table[:table.index("## All rows")]
    rows = [line for line in headline[:headline.index("**Who won.**")].splitlines() if line.startswith("| oracle")]
    assert "(1 entries): **too few entries to call" in headline  # who won, said with the evidence there is
    assert len(rows) == 3 and "LPIPS (all)" in headline and "PSNR (objects)" in headline and "n/a" not in rows[2]
    assert "LPIPS (whole) | LPIPS (all) | LPIPS (largest) | LPIPS (objects)" in table
    assert "| oracle: GT masks + semantics | 3D-SDN (ours) | G | generator, full (paper protocol) |" in table
    assert "| oracle: GT masks + semantics | 3D-SDN (ours) | G | generator, edited |" in table
    assert "| oracle: GT masks + semantics | 3D-SDN (ours) | none | photo (own pixels through 3D" in table
    assert "**Oracle rows only**" in table  # no row runs on predictions: said so
    assert "| edited-object mask IoU |" in table and "compose edited adds" in table
    assert "photo appearance takes" in table
    assert "## By kind of edit" in table
    grid = np.asarray(Image.open(out / "examples" / "0000.png"))
    assert 3 * 64 + 2 * 6 < grid.shape[0] < 3 * (64 + 30) + 2 * 6  # one titled row per mode
    page = (out / "index.html").read_text()
    assert 'src="examples/0000.png"' in page and (out / "examples" / "0000.png").is_file()
    assert "oracle: ground-truth masks and semantics" in page
    assert "3D-SDN (ours)" in capsys.readouterr().out
    bad = args[:-2] + [f"output_dir={tmp_path / 'b2'}", "proposals=gt"]
    assert main(bad + [f"benchmark={tmp_path / 'none.json'}"]) == 2
    assert main(bad + ["checkpoints.textural=null"]) == 2
    assert "checkpoints.textural is required" in capsys.readouterr().err and not (tmp_path / "b2").exists()
    assert main(bad + ["compose=[full,partial]"]) == 2
    assert "compose must list distinct modes of ('photo', 'edited', 'full'), got ['full', 'partial']" in \
        capsys.readouterr().err
    assert main(bad + ["proposals=[gt,auto]"]) == 2
    assert "proposals must list distinct values of ['semantic', 'gt']" in capsys.readouterr().err
    assert main(bad[:-2] + [f"output_dir={tmp_path / 'paper'}", "proposals=gt", "compose=full"]) == 0
    table = (tmp_path / "paper" / "table1.md").read_text()
    assert "| G | generator, edited |" not in table
    assert "| 3D-SDN (ours) | G | generator, full (paper protocol) |" in table


def test_bench_cli_needs_a_semantic_checkpoint_for_its_default_predicted_row(tiny_synth, tmp_path, capsys):
    """The default proposals=[semantic, gt]: without checkpoints.semantic the predicted row cannot be computed, and
    the run says so instead of reporting the oracle row alone (nothing written)."""
    ckpts = write_checkpoints(tmp_path / "ckpt")
    out = tmp_path / "bench"
    assert main(_cli_args(tiny_synth, ckpts, out)) == 2
    err = capsys.readouterr().err
    assert "proposals=['semantic', 'gt'] asks for the predicted row" in err and "checkpoints.semantic is null" in err
    assert "or proposals=gt for the oracle row alone" in err and not out.exists()


def _first_entry_world(report: dict) -> str:
    """The world of the run's first entry (``key``: ``world/variation source->target``)."""
    return report["entries"]["gt"][0]["key"].split("/")[0]


def test_bench_cli_reports_the_predicted_row_first_and_the_oracle_row_labelled(tiny_synth, tmp_path):
    ckpts = write_checkpoints(tmp_path / "ckpt")
    out = tmp_path / "bench"
    assert main(_cli_args(tiny_synth, ckpts, out, f"checkpoints.semantic={ckpts['semantic']}", "compose=full")) == 0
    report = json.loads((out / "results.json").read_text())
    info = report["info"]
    assert info["sources"] == ["semantic", "gt"] and info["source_oracle"] == {"semantic": False, "gt": True}
    assert info["source_labels"]["semantic"] == "predicted: the semantic branch's masks and semantics"
    assert set(report["summary"]) == set(report["entries"]) == {"semantic", "gt"}
    assert report["config"]["proposals"] == ["semantic", "gt"]  # the default
    # each entry names the cars it edits (world/ground-truth instance id), the same in both rows: the intervals'
    # resampling groups (edited_car_groups)
    for row in ("semantic", "gt"):
        cars = [e["cars"] for e in report["entries"][row] if not e["errors"].get("entry")]
        assert cars and all(c and all(x.startswith(f"{_first_entry_world(report)}/") for x in c) for c in cars)
    assert [e["cars"] for e in report["entries"]["semantic"]] == [e["cars"] for e in report["entries"]["gt"]]
    table = (out / "table1.md").read_text()
    rows = [line.split(" | ")[0] for line in table.splitlines()
            if line.startswith(("| predicted", "| oracle")) and "] | " not in line]  # not the who-won intervals
    # headline, L1/SSIM/PSNR table (3 methods each), layout table and each kind's: predicted rows before oracle rows
    assert len(rows) >= 24 and rows == (["| predicted"] * 3 + ["| oracle: GT masks + semantics"] * 3) * (len(rows) // 6)
    assert "*predicted* = predicted: the semantic branch's masks and semantics" in table
    assert "*oracle: GT masks + semantics* = oracle: ground-truth masks and semantics" in table
    assert "**Oracle rows only**" not in table
    page = (out / "index.html").read_text()
    assert page.index("row 1: predicted") < page.index("row 2: oracle: ground-truth masks and semantics")
    grid = np.asarray(Image.open(out / "examples" / "0000.png"))
    assert 2 * 64 + 6 < grid.shape[0] < 2 * (64 + 30) + 6  # one titled row per source scene (compose=full)


class _PerfectSemantic(torch.nn.Module):
    """A semantic branch that predicts the frame's ground truth (the benchmark's predicted row then sees the
    oracle's masks through the branch's path); counts its calls."""

    def __init__(self, maps):
        super().__init__()
        self.maps, self.calls = maps, 0
        self.classes = class_list("vkitti")

    def forward(self, image):
        from types import SimpleNamespace

        self.calls += 1
        label, instance = self.maps
        return SimpleNamespace(label=label[None], instance=instance[None])


def test_predicted_row_runs_the_semantic_branch(bench, models):
    entries, records = bench
    entry = entries[0]
    source = records[(entry.world, entry.variation, entry.source_frame)]
    from sdn3d.data.scene_gt import ground_truth

    gt = ground_truth(source, SIZE)
    semantic = _PerfectSemantic((gt.semantic, gt.instances))
    predicted = Models(semantic, models.geometric, models.textural, crop_size=32)
    results = run_benchmark(entries, records, predicted, BenchSettings(image_size=SIZE, min_pixels=1, examples=0))
    assert semantic.calls == 1 and not results[0].errors  # proposals='semantic' is BenchSettings' default
    oracle = run_benchmark(entries, records, predicted, BenchSettings(image_size=SIZE, proposals="gt", min_pixels=1,
                                                                      examples=0))
    assert semantic.calls == 1  # the oracle row does not run the branch
    # the same masks: the edited objects land in the same places (geometry crops differ: mask vs annotation box)
    iou = {k: r[0].metrics["full"]["3d-sdn"]["layout"]["mask_iou"] for k, r in (("p", results), ("o", oracle))}
    assert math.isfinite(iou["p"]) and math.isfinite(iou["o"])
    with pytest.raises(UserInputError, match="proposals must be one of"):
        BenchSettings(proposals="auto")


def _write_textural_2d(folder, **overrides):
    """A textural checkpoint like helpers.tiny_models' one, trained-as-if with ``overrides`` (e.g. no pose maps)."""
    hp = dict(TEXTURAL_HP) | overrides
    spec = TexturalSpec.from_mapping(hp, num_classes=len(class_list(hp["classes"])))
    state = {f"generator.{k}": v for k, v in spec.generator().state_dict().items()}
    state |= {f"encoder.{k}": v for k, v in spec.encoder().state_dict().items()}
    path = folder / f"textural_2d_{len(list(folder.glob('*.ckpt')))}.ckpt"
    torch.save({"state_dict": state, "hyper_parameters": hp}, path)
    return path


def test_baselines_drawn_by_a_generator_without_3d_inputs(bench, models, tmp_path):
    """run_benchmark(baseline_textural=G2d): 2D and 2D+ go through G2d (no pose / normal channels), with codes from
    G2d's own encoder; 3D-SDN through G."""
    entries, records = bench
    g2d = TexturalRenderer.from_checkpoint(_write_textural_2d(tmp_path, use_pose=False, use_normal=False))
    assert g2d.generator.model[1].in_channels == 14 + 1 + 5
    seen = {"main": [], "2d": []}
    hooks = [models.textural.generator.register_forward_hook(lambda m, i, o: seen["main"].append(i[0].shape[1])),
             g2d.generator.register_forward_hook(lambda m, i, o: seen["2d"].append(i[0].shape[1]))]
    encoded = []
    encode = g2d.encode
    g2d.encode = lambda image, L: encoded.append(tuple(image.shape)) or encode(image, L)
    try:
        settings = BenchSettings(image_size=SIZE, proposals="gt", min_pixels=1, examples=1)
        with_2d = run_benchmark(entries, records, models, settings, baseline_textural=g2d)[0]
    finally:
        for h in hooks:
            h.remove()
    assert not with_2d.errors
    assert seen["main"] == [14 + 1 + 5 + 24 + 3] and seen["2d"] == [20, 20] and encoded == [(1, 3, 64, 160)]
    same = run_benchmark(entries, records, models, settings)[0]
    assert (same.images["full:3d-sdn"] == with_2d.images["full:3d-sdn"]).all()
    assert not (same.images["full:2d"] == with_2d.images["full:2d"]).all()
    for m in ("2d", "2d+"):  # compose edited: the edit region against G2d's own source maps, not the whole frame
        kept = (with_2d.images[f"edited:{m}"] == with_2d.images["source"]).all(-1)
        assert kept.any() and (~kept).any()


def test_bench_cli_says_which_generator_drew_each_row(tiny_synth, tmp_path, capsys):
    ckpts = write_checkpoints(tmp_path / "ckpt")
    g2d = _write_textural_2d(tmp_path, use_pose=False, use_normal=False)
    out = tmp_path / "bench"
    base = _cli_args(tiny_synth, ckpts, out, "proposals=gt", "compose=full")
    assert main(base) == 0  # without textural_2d: the 3D-informed generator draws 2D / 2D+, and the table says so
    report = json.loads((out / "results.json").read_text())
    gens = report["info"]["generators"]
    assert gens["2d"] == gens["2d+"] == gens["3d-sdn"]
    assert gens["2d"]["checkpoint"] == str(ckpts["textural"]) and gens["2d"]["use_pose"] and gens["2d"]["use_normal"]
    table = (out / "table1.md").read_text()
    assert "| oracle: GT masks + semantics | 2D | G | generator, full (paper protocol) |" in table
    assert "The 2D and 2D+ rows use the 3D-informed generator" in table
    assert main([*base, f"checkpoints.textural_2d={g2d}"]) == 0
    report = json.loads((out / "results.json").read_text())
    gens = report["info"]["generators"]
    assert gens["2d"] == gens["2d+"] and gens["2d"]["checkpoint"] == str(g2d) and gens["2d"]["tag"] == "G-2D"
    assert not gens["2d"]["use_pose"] and not gens["2d"]["use_normal"] and gens["3d-sdn"]["use_pose"]
    table = (out / "table1.md").read_text()
    assert "| oracle: GT masks + semantics | 2D+ | G-2D | generator, full (paper protocol) |" in table
    assert "| oracle: GT masks + semantics | 3D-SDN (ours) | G | generator, full (paper protocol) |" in table
    assert f"- G-2D: `{g2d}` (inputs: semantics, boundaries, texture codes): draws 2D, 2D+" in table
    assert "3D-informed generator" not in table
    assert "without pose / normal maps" in (out / "index.html").read_text()
    capsys.readouterr()
    bad = [*base[:-3], f"output_dir={tmp_path / 'b2'}", "proposals=gt"]
    assert main([*bad, f"checkpoints.textural_2d={tmp_path / 'none.ckpt'}"]) == 2
    assert "checkpoints.textural_2d" in capsys.readouterr().err
    other = _write_textural_2d(tmp_path, classes="cityscapes", use_pose=False, use_normal=False)
    assert main([*bad, f"checkpoints.textural_2d={other}"]) == 2
    assert "draws 19 classes, checkpoints.textural 14" in capsys.readouterr().err and not (tmp_path / "b2").exists()


def test_occluder_removed_entries_are_summarised_apart():
    """Table 1's means are over the paper's kind of entry; "occluder removed" ones get their own summary."""
    from sdn3d.evaluation.edit_benchmark import METHODS

    def result(i: int, kind: str, l1: float) -> EntryResult:
        row = {"all": {"l1": l1}, "layout": {"mask_iou": 0.5}}
        return EntryResult(i, f"e{i}", 1, kind=kind, metrics={"full": {m: dict(row) for m in METHODS}})

    summary = summarize([result(0, "edit", 0.1), result(1, "edit", 0.3), result(2, "occluder_removed", 0.9)])
    assert summary["entries"] == 2 and summary["methods"]["full"]["3d-sdn"]["all"]["l1"]["mean"] == pytest.approx(0.2)
    removed = summary["by_kind"]["occluder_removed"]
    assert removed["entries"] == 1 and removed["methods"]["full"]["2d"]["all"]["l1"]["mean"] == pytest.approx(0.9)
    assert result(2, "occluder_removed", 0.9).to_json()["kind"] == "occluder_removed"


def test_baseline_photos_share_one_removal_and_equal_each_baseline_photo(bench, monkeypatch):
    """The 2D and 2D+ photo baselines remove (and fill) the same objects: baseline_photos fills the hole once and
    gives each mode's picture exactly as baseline_photo does."""
    import sdn3d.evaluation.baselines as baselines
    from sdn3d.data.frames import load_frame
    from sdn3d.editing.photo.settings import PhotoSettings

    entries, records = bench
    modifies = [e for e in entries if any(op.kind == "modify" for op in e.operations)]
    assert modifies
    entry = modifies[0]
    source = records[(entry.world, entry.variation, entry.source_frame)]
    scene = scene_from_frame(source, SIZE)
    image = load_frame(source, SIZE, semantic=False, instances=False).image
    fills = []
    real_fill = baselines.fill_hole
    for fill in ("rays", "telea"):
        settings = PhotoSettings(fill=fill)
        expected = {m: baselines.baseline_photo(image, scene, entry, m, settings=settings) for m in ("2d", "2d+")}
        fills.clear()
        monkeypatch.setattr(baselines, "fill_hole", lambda *a, **k: fills.append(1) or real_fill(*a, **k))
        got = baselines.baseline_photos(image, scene, entry, ("2d", "2d+"), settings=settings)
        monkeypatch.setattr(baselines, "fill_hole", real_fill)
        assert len(fills) == 1 and list(got) == ["2d", "2d+"]
        for m in got:
            assert torch.equal(got[m], expected[m]), (fill, m)
        assert got["2d"].data_ptr() != got["2d+"].data_ptr()  # each mode its own tensor
