"""The demo pipeline end to end (small config) and the mesh-placement bridge it uses."""

from __future__ import annotations

import json

import pytest
import torch
from hydra import compose, initialize_config_dir

from sdn3d.cli._config import CONFIG_DIR
from sdn3d.math3d.ffd import expand_half_ffd
from sdn3d.math3d.transforms import object_to_camera
from sdn3d.meshes import MeshBank
from sdn3d.models import Models
from sdn3d.render.objects import pose_meshes


def test_pose_meshes_matches_object_to_camera_and_keeps_padding_degenerate():
    bank = MeshBank.templates()
    ids = torch.tensor([0, 7, 3])
    dims = torch.tensor([[4.5, 1.5, 1.8], [12.0, 3.2, 2.5], [4.8, 1.8, 1.9]])
    ry = torch.tensor([0.3, -1.0, 2.0])
    center = torch.tensor([[1.0, 0.9, 10.0], [-3.0, 0.0, 30.0], [4.0, 0.8, 15.0]])
    verts, faces = pose_meshes(bank, ids, dims, ry, center)
    for row, t in enumerate(ids.tolist()):
        nv = int(bank.num_verts[t])
        expected = object_to_camera(bank.verts[t : t + 1, :nv], dims[row : row + 1], ry[row : row + 1],
                                    center[row : row + 1])[0]
        torch.testing.assert_close(verts[row, :nv], expected)
        # padding vertices sit on the centre, so padding faces (0, 0, 0) stay degenerate
        assert torch.allclose(verts[row, nv:], center[row].expand_as(verts[row, nv:]))
    # a symmetric FFD moves the mesh and stays differentiable
    phi_half = (0.05 * torch.randn(3, 32, 3)).requires_grad_(True)
    moved, _ = pose_meshes(bank, ids, dims, ry, center, expand_half_ffd(phi_half))
    assert (moved - verts).abs().max() > 1e-3
    moved.sum().backward()
    assert phi_half.grad is not None and torch.isfinite(phi_half.grad).all()


def test_demo_runs_end_to_end(tmp_path):
    from sdn3d.cli.render_demo import run_demo

    with initialize_config_dir(config_dir=CONFIG_DIR, version_base="1.3"):
        cfg = compose(
            config_name="render_demo",
            overrides=[
                f"output_dir={tmp_path / 'demo'}",
                f"data_dir={tmp_path / 'data'}",
                "threads=1",
                "synth.frames_per_sequence=2",
                "synth.edit_pairs=0",
                "fit.steps=40",
            ],
        )
    summary = run_demo(cfg)
    out = tmp_path / "demo"
    for name in ("maps.png", "silhouette_fit.png", "edit_maps.png", "report.md", "summary.json", "frame_rgb.png"):
        assert (out / name).is_file(), name
    saved = json.loads((out / "summary.json").read_text())
    assert saved["frame"] == summary["frame"]
    # rendering the annotated templates reproduces the dataset's vehicle pixels closely
    assert saved["template_render_vehicle_iou"] > 0.9
    fit = saved["silhouette_fit"]
    assert fit["iou_final"] > fit["iou_start"] + 0.05
    assert "Short CPU run" in (out / "report.md").read_text()


def test_full_demo_tiny_budget(tmp_path):
    """The README's main command end to end (train 3 branches, benchmark, edits, report) on a tiny budget."""
    from sdn3d.cli.demo import main

    out = tmp_path / "demo"
    status = main([f"output_dir={out}", f"data_dir={tmp_path / 'data'}", "threads=1", "synth.image_size=[160,64]",
                   "synth.worlds=[0001]", "synth.frames_per_sequence=5", "synth.edit_pairs=2", "synth.workers=1",
                   'train.common=["data.image_size=[160,64]","trainer.max_steps=2","trainer.limit_val_batches=1","trainer.limit_test_batches=1",'
                   '"trainer.enable_progress_bar=false","trainer.num_sanity_val_steps=0"]',
                   "train.semantic=[]", "train.geometric=[]", "train.textural=[]",
                   "bench.limit=1", "bench.examples=1", "edits.angles_deg=[45]", "render_size=null"])
    assert status == 0
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["training"]) == {"semantic", "geometric", "textural"}
    assert all(s["status"] == "ok" for s in summary["training"].values())
    for name in ("report.md", "bench/table1.md", "bench/index.html", "edits/edits_grid.png", "edits/deleted.png",
                 "edits/recoloured_red.png", "edits/rotated_p45_deg.png", "edits/closer.png",
                 "edits/sources/deleted.png"):
        assert (out / name).is_file(), name
    report = (out / "report.md").read_text()
    assert "short CPU run" in report and "| 3D-SDN" in report
    # the benchmark on predictions first (the demo trains a semantic branch), then the oracle row, labelled
    assert 0 < report.index("| predicted | 2D |") < report.index("| oracle: GT masks + semantics | 2D |")
    assert summary["bench"]["info"]["sources"] == ["semantic", "gt"]
    # the predicted rows' proposals are measured: recall of the test part's vehicles, said in the report
    recall = summary["proposal_recall"]
    assert recall["min_pixels"] == 256 and recall["frames"] > 0 and recall["proposals"] >= 0
    assert "The semantic branch's proposals (the predicted rows' objects) find" in report
    assert summary["peak_memory"]["largest_child_mib"] > 0
    # the first screen: the labelled edits, a line per branch, Table 1's headline; no column is all n/a
    first = report.split("\n## Details\n")[0]
    assert "](edits/edits_grid.png)" in first and "Table 1, headline" in first and "| 3D-SDN (ours) |" in first
    assert [line.split("**")[1] for line in first.split("\n") if line.startswith("- **")] == \
        ["semantic", "geometric", "textural"]
    assert _empty_columns(report) == []


def test_demo_composes_the_medium_and_long_budgets():
    from sdn3d.cli._config import compose_config

    long = compose_config(["budget=long"], "demo")
    assert long.budget_name == "long" and long.train.experiment.geometric == "demo_long" and long.gpu_budget
    medium = compose_config(["budget=medium"], "demo")
    assert medium.train.branches == ["semantic", "geometric", "textural"] and medium.render_size == [312, 96]
    assert len(long.synth.worlds) == 5 and long.train.textural == []  # the budget is in experiment=demo_long


@pytest.mark.slow  # 20 s: two training processes at once; test_full_demo_tiny_budget runs the same stages in turn
def test_demo_trains_branches_in_parallel(tmp_path):
    from sdn3d.cli.demo import main

    out = tmp_path / "demo"
    status = main([f"output_dir={out}", f"data_dir={tmp_path / 'data'}", "threads=1", "synth.image_size=[160,64]",
                   "synth.worlds=[0001]", "synth.frames_per_sequence=5", "synth.edit_pairs=1", "synth.workers=1",
                   "train.parallel=true", "train.branches=[geometric,textural]",
                   'train.common=["data.image_size=[160,64]","trainer.max_steps=2","trainer.limit_val_batches=1",'
                   '"trainer.limit_test_batches=1","trainer.num_sanity_val_steps=0"]',
                   "train.geometric=[]", "train.textural=[]", "bench.limit=1", "bench.examples=1",
                   "render_size=[128,48]", "edits.angles_deg=[45]"])
    assert status == 0
    summary = json.loads((out / "summary.json").read_text())
    assert set(summary["training"]) == {"geometric", "textural"} and summary["budget"] == "short"
    for branch in ("geometric", "textural"):  # each child's output went to its own file
        assert (out / "runs" / f"{branch}.out").stat().st_size > 0
        assert (out / "runs" / branch / "summary.json").is_file()
    assert (out / "bench" / "table1.md").is_file()
    from PIL import Image  # benchmark and edits at render_size, not the data's 160x64

    assert summary["data"]["render_size"] == [128, 48]
    # the photo appearance (the default): the edits at the frame's own 160x64, whatever the render size
    assert Image.open(out / "edits" / "deleted.png").size == (160, 64)
    assert Image.open(out / "edits" / "sources" / "deleted.png").size == (160, 64)


@pytest.mark.parametrize("mode", ["edited", "full"])
def test_demo_edits_are_composed_into_the_frame(tiny_synth, tmp_path, mode):
    """``edits.compose=edited``: every example edit is the frame at its own size with only the edit region
    redrawn; ``full``: the generator's pictures at render_size."""
    import numpy as np
    from helpers.tiny_models import write_checkpoints
    from PIL import Image

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.demo import run_edits
    from sdn3d.data import vkitti1

    ckpts = {k: str(v) for k, v in write_checkpoints(tmp_path / "ckpt").items()}
    (tmp_path / "config.yaml").write_text("datamodule:\n  crop_size: 32\n")  # the geometric run's crop size
    # Random weights put cars anywhere: move the car away (zoom < 1) so that no edit reaches the near plane.
    cfg = compose_config(["render_size=[80,32]", "edits.angles_deg=[45]", "edits.zoom=0.8", f"edits.compose={mode}",
                          "edits.appearance=generator"], "demo")
    info = run_edits(cfg, tiny_synth, ckpts, tmp_path / "edits")
    assert info["compose"] == mode and info["picture_size"] == ([160, 64] if mode == "edited" else [80, 32])
    frame = [r for r in vkitti1.read_frames(tiny_synth) if r.key == info["frame"]][0]
    original = vkitti1.load_rgb(frame)
    pictures = {n: np.asarray(Image.open(tmp_path / "edits" / f"{n}.png"))
                for n in ("reconstruction", "deleted", "recoloured_red", "rotated_p45_deg")}
    generated = np.asarray(Image.open(tmp_path / "edits" / "generated" / "deleted.png"))
    assert generated.shape == (32, 80, 3)
    if mode == "full":
        assert (pictures["deleted"] == generated).all()
        return
    for name, picture in pictures.items():
        assert picture.shape == original.shape
        kept = (picture == original).all(-1).mean()
        assert (kept < 0.05) if name == "reconstruction" else (0.3 < kept < 1), (name, kept)
    grid = np.asarray(Image.open(tmp_path / "edits" / "edits_grid.png"))
    rows = (1 + len(info["edits"]) + 1) // 2  # source + reconstruction, then two edits a row (the last one alone)
    band = grid.shape[0] // rows - 64 - 6  # every panel under its title band
    assert 10 <= band <= 30 and (grid[band:band + 64, :160] == original).all()  # the source panel is the frame


def test_demo_edits_in_photo_appearance_keep_the_frame_and_title_every_panel(tiny_synth, tmp_path):
    """The default ``edits.appearance=photo``: every edit is the frame at its own size, changed only around the car;
    the recolour repaints it; each panel of the grid has a title band; ``sources/`` says where pixels came from."""
    import numpy as np
    from helpers.tiny_models import write_checkpoints
    from PIL import Image

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.demo import run_edits
    from sdn3d.data import vkitti1

    ckpts = {k: str(v) for k, v in write_checkpoints(tmp_path / "ckpt").items()}
    (tmp_path / "config.yaml").write_text("datamodule:\n  crop_size: 32\n")
    cfg = compose_config(["render_size=[80,32]", "edits.angles_deg=[45]", "edits.zoom=0.8", "edits.proposals=gt"],
                         "demo")
    info = run_edits(cfg, tiny_synth, ckpts, tmp_path / "edits")
    assert info["appearance"] == "photo" and info["picture_size"] == [160, 64]
    assert "reconstruction" not in info["edits"] and info["grid_layout"][0] == "source"
    frame = [r for r in vkitti1.read_frames(tiny_synth) if r.key == info["frame"]][0]
    original = vkitti1.load_rgb(frame)
    for name in ("deleted", "recoloured_red", "rotated_p45_deg", "closer"):
        picture = np.asarray(Image.open(tmp_path / "edits" / f"{name}.png"))
        sources = np.asarray(Image.open(tmp_path / "edits" / "sources" / f"{name}.png"))
        assert picture.shape == original.shape == sources.shape
        kept = (picture == original).all(-1)
        assert 0.3 < kept.mean() < 1, name  # the frame, changed around the edited car only
    grid = np.asarray(Image.open(tmp_path / "edits" / "edits_grid.png"))
    rows = (1 + len(info["edits"]) + 1) // 2
    band = grid.shape[0] // rows - 64 - 6
    assert 10 <= band <= 30 and (grid[:band, :160] > 200).mean() > 0.7  # a white title band with dark text
    assert (grid[:band, :160] < 100).any() and (grid[band:band + 64, :160] == original).all()


def test_demo_benchmark_and_edits_run_on_predicted_proposals(tiny_synth, tmp_path):
    """The demo's benchmark reports the predicted row first, then the oracle row (only the oracle, said so, when no
    semantic branch was trained); its example edits de-render with the semantic branch, and fall back to the
    frame's masks, labelled as the oracle, when the branch finds no car with geometry."""
    from helpers.tiny_models import write_checkpoints

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.demo import _recall_note, bench_proposals, run_edits, run_proposal_recall

    cfg = compose_config(["render_size=[80,32]", "edits.angles_deg=[45]", "edits.zoom=0.8"], "demo")
    ckpts = {k: str(v) for k, v in write_checkpoints(tmp_path / "ckpt").items()}
    assert list(cfg.bench.proposals) == ["semantic", "gt"] and cfg.edits.proposals == "semantic"
    assert bench_proposals(cfg, ckpts) == ["semantic", "gt"]
    assert bench_proposals(cfg, {"geometric": ckpts["geometric"], "textural": ckpts["textural"]}) == ["gt"]
    # the recall of the semantic branch's proposals on the test part (the report's sentence); none without it
    recall = run_proposal_recall(cfg, tiny_synth, ckpts)
    assert recall["frames"] > 0 and recall["objects"] > 0 and 0.0 <= recall["recall"] <= 1.0
    assert recall["work_size"] == [80, 32]
    assert f"of the test part's {recall['objects']} vehicles over 256" in _recall_note(recall)
    assert run_proposal_recall(cfg, tiny_synth, {"geometric": ckpts["geometric"]}) is None
    assert "oracle" in _recall_note(None)
    (tmp_path / "config.yaml").write_text("datamodule:\n  crop_size: 32\n")  # the geometric run's crop size
    info = run_edits(cfg, tiny_synth, ckpts, tmp_path / "edits")
    # random semantic weights propose no car with geometry on tiny_synth: the oracle stands in, labelled
    assert info["proposals"].startswith("oracle: ground-truth masks and semantics (the semantic branch found no car")
    assert info["grid_titles"][0].endswith("; objects: oracle, ground-truth masks")  # said on the figure too
    oracle = compose_config(["render_size=[80,32]", "edits.angles_deg=[45]", "edits.zoom=0.8", "edits.proposals=gt"],
                            "demo")
    info = run_edits(oracle, tiny_synth, ckpts, tmp_path / "e2")
    assert info["proposals"] == "oracle: ground-truth masks and semantics"
    assert info["grid_titles"][0] == f"source: {info['frame']}, car {info['car']}; objects: oracle, ground-truth masks"
    # a semantic run whose recorded validation quality is too low to trust (the short budget's): the oracle, said why
    (tmp_path / "summary.json").write_text(json.dumps({"metrics": {"val/pq": 0.0, "val/miou": 0.17}}))
    info = run_edits(cfg, tiny_synth, ckpts, tmp_path / "e3")
    assert info["proposals"].startswith("oracle: ground-truth masks and semantics (the semantic branch's recorded "
                                        "val/pq is 0.000")


def test_demo_bad_override_exits_2_without_output(tmp_path, capsys):
    from sdn3d.cli.demo import main

    assert main([f"output_dir={tmp_path / 'demo'}", "no_such_key=1"]) == 2
    assert "bad configuration override" in capsys.readouterr().err
    assert not (tmp_path / "demo").exists()


def _tables(markdown: str) -> list[list[list[str]]]:
    """Every markdown table of ``markdown`` as rows of cells (header, separator, body)."""
    tables, current = [], []
    for line in markdown.split("\n") + [""]:
        if line.startswith("|"):
            current.append([c.strip() for c in line.strip().strip("|").split("|")])
        elif current:
            tables.append(current)
            current = []
    return tables


def _empty_columns(markdown: str) -> list[str]:
    """Headers of table columns whose every body cell is n/a or blank."""
    return [t[0][k] for t in _tables(markdown) if len(t) > 2 for k in range(len(t[0]))
            if all(k < len(r) and r[k] in ("n/a", "") for r in t[2:])]


def _report_info(root: str) -> dict:
    """What run_demo gathers (summary.json), with recorded figures of a short run."""
    return {
        "seed": 0, "threads": 2, "device": "cpu", "budget": "short", "wall_s": 156.0,
        "stages_s": {"data": 4.0}, "peak_memory": {"largest_child_mib": 1223.0, "demo_process_mib": 871.0},
        "data": {"root": root, "frames": 42, "image_size": [624, 192], "render_size": [312, 96]},
        "training": {
            "semantic": {"global_step": 12, "demo_wall_s": 28.8, "metrics": {
                "test/miou": 0.0904, "test/pq": 0.0, "test/pq_Car": 0.0, "test/pq_Van": 0.0, "val/pq": 0.0,
                "val/pq_Car": 0.0, "val/pq_Van": 0.0, "val/miou": 0.0976}},
            "geometric": {"global_step": 40, "demo_wall_s": 22.5, "metrics": {
                "test/mesh_accuracy": 0.1296, "test/mesh_majority_floor": 0.1852, "test/mesh_uniform_floor": 0.125,
                "test/mesh_identifiability_ceiling": 0.537, "test/orientation_similarity": 0.9012,
                "test/reprojection_error_image": 0.003059}},
            "textural": {"global_step": 240, "demo_wall_s": 77.7, "metrics": {
                "test/psnr": 16.54, "test/l1": 0.1093, "test/obj_psnr": 14.09}}},
        "proposal_recall": {"frames": 18, "objects": 62, "recall": 0.5, "precision": 0.75, "proposals": 41,
                            "per_class": {"Car": {"objects": 46, "recall": 0.5}}, "min_pixels": 256, "iou": 0.5},
        "edits": {"frame": "vkitti1/0002/clone/00014", "car": 12005, "grid": "edits/edits_grid.png",
                  "grid_layout": ["source", "closer (zoom 1.6)", "deleted"], "edit_render_s": {"deleted": 0.3},
                  "appearance": "photo", "compose": "edited", "recoloured": "red", "derender_s": 0.05,
                  "proposals": "predicted: the semantic branch's masks and semantics", "picture_size": [624, 192]},
    }


_TABLE1 = """# Editing benchmark: headline

8 entries, mode **photo**.

| Scene | Method | LPIPS (all) | L1 (all) | PSNR (all) |
|---|---|---|---|---|
| predicted | 2D | n/a | 0.1620 | 12.98 |
| predicted | 3D-SDN (ours) | n/a | 0.1917 | 12.86 |

# Editing benchmark (3D-SDN Table 1 layout)

## All rows

| Scene | Method | LPIPS (whole) | LPIPS (all) | L1 (all) |
|---|---|---|---|---|
| predicted | 2D | n/a | n/a | 0.1620 |
| predicted | 3D-SDN (ours) | n/a | n/a | 0.1917 |

**Delete** (1 entries):

| Scene | Mode | Method | L1 (all) | PSNR (objects) | mask IoU |
|---|---|---|---|---|---|
| predicted | photo | 2D | 0.1679 | n/a | n/a |
| predicted | photo | 3D-SDN (ours) | 0.1679 | n/a | 0.5 |
"""


def test_report_first_screen_shows_the_edits_the_branches_and_table1_without_empty_columns(tmp_path):
    """The report opens with the labelled before/after figure (linked relative to report.md), one line per branch
    with its figure beside its floor, and Table 1's headline; no column is all n/a; the caveats follow below."""
    from sdn3d.cli.demo import drop_empty_columns, write_report

    out = tmp_path / "demo"
    (out / "bench").mkdir(parents=True)
    (out / "bench" / "table1.md").write_text(_TABLE1)
    assert _empty_columns(_TABLE1) == ["LPIPS (all)", "LPIPS (whole)", "LPIPS (all)", "PSNR (objects)"]
    report = write_report(out, _report_info(str(tmp_path / "data")))
    assert (out / "report.md").read_text() == report and (out / "summary.json").is_file()
    first, details = report.split("\n## Details\n")
    assert report.startswith("# sdn3d demo report\n\n![") and "](edits/edits_grid.png)" in first.split("\n")[2]
    assert "car 12005 (the largest found wholly in view): source, closer (zoom 1.6), deleted" in first
    branches = [line for line in first.split("\n") if line.startswith("- **")]
    assert [b.split("**")[1] for b in branches] == ["semantic", "geometric", "textural"]
    semantic, geometric, textural = branches
    assert "test mIoU 0.090" in semantic and "validation vehicle PQ 0.000 against the 0.3" in semantic
    assert "find 31 of the test part's 62 vehicles (recall 0.50, precision 0.75)" in semantic
    assert "mesh accuracy 0.130 (under its majority floor 0.185; uniform 0.125" in geometric
    assert "orientation similarity 0.901" in geometric and "reprojection error 3.06 x1e-3" in geometric
    assert "test PSNR 16.54 dB" in textural and "no floor recorded" in textural
    # Table 1's headline rows on the first screen, the LPIPS column (every cell n/a) left out
    assert "| predicted | 3D-SDN (ours) | 0.1917 | 12.86 |" in first and "LPIPS" not in first
    assert len(first.split("\n")) < 30  # one screen, the figure included
    # the detail follows: caveats, the training table, every benchmark table, less their empty columns
    assert "short CPU run" in details and "short CPU run" not in first
    assert "| Scene | Method | L1 (all) |" in details
    assert "| predicted | photo | 3D-SDN (ours) | 0.1679 | 0.5 |" in details
    assert "#### All rows" in details  # table1's headings sit under the report's
    assert _empty_columns(report) == [] and "n/a | n/a" not in report
    # a table whose columns all have values is left as it is; text is untouched
    assert drop_empty_columns("a | b\n\n| x | y |\n|---|---|\n| 1 | 2 |") == "a | b\n\n| x | y |\n|---|---|\n| 1 | 2 |"


def test_report_first_screen_without_a_semantic_branch_or_benchmark(tmp_path):
    """Without a semantic branch (train.branches) or benchmark table the first screen still has the figure and a
    line per trained branch, and says nothing it did not measure."""
    from sdn3d.cli.demo import write_report

    info = _report_info(str(tmp_path / "data"))
    del info["training"]["semantic"]
    info["proposal_recall"] = None
    report = write_report(tmp_path, info)
    first = report.split("\n## Details\n")[0]
    assert "](edits/edits_grid.png)" in first and "Table 1, headline" not in first
    assert [line.split("**")[1] for line in first.split("\n") if line.startswith("- **")] == ["geometric", "textural"]
    assert "(not run)" in report


def test_report_names_the_semantic_runs_recorded_proposal_figures_and_whether_they_are_trusted():
    """A semantic run that recorded its validation proposal recall and precision is judged by them (what the edits
    need), not by its vehicle PQ, on the report's first screen."""
    from sdn3d.cli.demo import branch_lines

    summary = {"global_step": 396, "demo_wall_s": 282.1, "metrics": {
        "test/miou": 0.476, "val/pq_Car": 0.2, "val/pq_Van": 0.29, "val/proposal_recall": 0.71,
        "val/proposal_precision": 0.68}}
    [line] = branch_lines({"semantic": summary}, {"recall": 0.78, "objects": 150, "precision": 0.75})
    assert "validation proposal recall 0.710 and precision 0.680 against the 0.5 each needs to be trusted (trusted)" \
        in line and "validation vehicle PQ" not in line
    assert "find 117 of the test part's 150 vehicles (recall 0.78, precision 0.75)" in line
    summary["metrics"]["val/proposal_precision"] = 0.4
    [line] = branch_lines({"semantic": summary}, None)
    assert "(not trusted)" in line


def test_the_example_car_is_the_largest_found_car_wholly_in_view(tiny_synth, monkeypatch):
    """_found_example: over the test frames, the largest proposal with geometry wholly in the picture that found
    (IoU >= 0.5) an annotated car the image does not cut; the branches' scene stands in here as the ground truth's
    own, so the choice is the largest untruncated car whose mask touches no left, right or bottom edge. It
    de-renders only the frames whose bound (twice their largest such car's pixels) reaches the best found, and
    chooses as de-rendering every frame would."""
    import sdn3d.derender as derendering
    from sdn3d.cli._config import synth_data_source
    from sdn3d.cli.demo import _found_example
    from sdn3d.data.records import load_rgb
    from sdn3d.data.scene_gt import scene_from_frame
    from sdn3d.data.sources import load_split

    source = synth_data_source(tiny_synth)
    records = [r for r in load_split(source, "test") if r.objects]
    by_key = {r.key: r for r in records}
    derendered = []

    def stand_in(image, intrinsics, models, proposals, gt, **kwargs):
        assert models.textural is None  # the search reads masks and geometry: no texture codes pooled
        stored = torch.from_numpy(load_rgb(by_key[gt.key])).permute(2, 0, 1).float() / 255
        assert torch.equal(kwargs["photo"].image, stored)  # the geometric crops read from the frame as stored
        derendered.append(gt.key)
        return scene_from_frame(by_key[gt.key], tuple(source.image_size))

    monkeypatch.setattr(derendering, "derender", stand_in)
    record, car = _found_example(records, source, Models(textural="textural branch"), "cpu")
    candidates = []  # every frame's, de-rendered here
    for order, r in enumerate(records):
        t = scene_from_frame(r, tuple(source.image_size)).objects
        whole = {o.track_id + 1 for o in r.objects if o.truncr == 0 and o.label in ("Car", "Van")}
        for row in range(len(t)):
            m = t.mask[row].bool()
            edge = bool(m[:, 0].any() or m[:, -1].any() or m[-1, :].any())
            if bool(t.has_geometry[row]) and not edge and int(t.instance_id[row]) % 1000 in whole \
                    and int(t.instance_id[row]) // 1000 in (12, 13):
                candidates.append((int(m.sum()), -order, r.key, int(t.instance_id[row])))
    area, _, key, iid = max(candidates)
    assert (record.key, car) == (key, iid)
    assert len(derendered) == len(set(derendered))  # each frame at most once


def test_the_example_search_skips_frames_that_cannot_hold_a_larger_car(monkeypatch):
    """_found_example de-renders the frames by their bound (twice their largest whole car's pixels), largest first,
    and stops at the first below the best found; of equal areas it keeps the first frame in the records' order."""
    from types import SimpleNamespace

    import sdn3d.data.frames as frames
    import sdn3d.data.scene_gt as scene_gt
    import sdn3d.derender as derendering
    from sdn3d.cli.demo import _found_example

    # per frame: (pixels of its car in the annotation, pixels of the proposal that found it: a part of it)
    cars: list[tuple[int, int]] = []

    def block(pixels: int) -> torch.Tensor:  # a block of `pixels` in the middle of a 40x40 frame, off every edge
        m = torch.zeros(40, 40, dtype=torch.bool)
        rows, last = divmod(pixels, 20)
        m[5:5 + rows, 10:30] = True
        m[5 + rows, 10:10 + last] = True
        return m

    def load_frame(record, size, **kwargs):
        truth = block(cars[int(record.key[1:])][0])
        return SimpleNamespace(instances=truth.long() * 12001, image=torch.zeros(3, 40, 40),
                               intrinsics=SimpleNamespace(width=40, height=40))

    derendered = []

    def derender(image, intrinsics, models, proposals, gt, **kwargs):
        derendered.append(gt)
        mask = block(cars[int(gt[1:])][1])[None]
        return SimpleNamespace(objects=SimpleNamespace(mask=mask, has_geometry=torch.ones(1, dtype=torch.bool),
                                                       instance_id=torch.tensor([12001])))

    monkeypatch.setattr(frames, "load_frame", load_frame)
    monkeypatch.setattr(scene_gt, "ground_truth", lambda record, size: record.key)
    monkeypatch.setattr(scene_gt, "frame_photo", lambda record, size: None)
    monkeypatch.setattr(derendering, "derender", derender)

    def search(frames_cars: list[tuple[int, int]]) -> str:
        cars[:] = frames_cars
        derendered.clear()
        records = [SimpleNamespace(key=f"f{i}", objects=[SimpleNamespace(track_id=0, label="Car", truncr=0.0)])
                   for i in range(len(cars))]
        record, car = _found_example(records, SimpleNamespace(image_size=(40, 40)), Models(), "cpu")
        assert car == 12001
        return record.key

    # bounds 60, 200, 80, 180, 90: f1 finds 100 px, f3 (bound 180) 90 px, and f4's bound 90 ends the search
    assert search([(30, 30), (100, 100), (40, 40), (90, 90), (45, 45)]) == "f1"
    assert derendered == ["f1", "f3"]
    # f1 (bound 140) and f0 (bound 120) both find 60 px: the first in the records' order is kept, as before
    assert search([(60, 60), (70, 60), (20, 20)]) == "f0"
    assert derendered == ["f1", "f0"]


def test_the_example_car_is_not_a_proposal_that_merged_two_cars(tiny_synth, monkeypatch):
    """_found_example passes over a proposal that took in a piece of another annotated car (more than
    EXAMPLE_MAX_FOREIGN of its pixels): every edit of the figure would drag that piece along."""
    import sdn3d.derender as derendering
    from sdn3d.cli._config import synth_data_source
    from sdn3d.cli.demo import _found_example
    from sdn3d.data.scene_gt import scene_from_frame
    from sdn3d.data.sources import load_split

    source = synth_data_source(tiny_synth)
    records = [r for r in load_split(source, "test") if r.objects]
    by_key = {r.key: r for r in records}

    def plain(image, intrinsics, models, proposals, gt, **kwargs):
        return scene_from_frame(by_key[gt.key], tuple(source.image_size))

    monkeypatch.setattr(derendering, "derender", plain)
    record, car = _found_example(records, source, Models(textural="textural branch"), "cpu")
    merged_key = record.key

    def merging(image, intrinsics, models, proposals, gt, **kwargs):
        scene = plain(image, intrinsics, models, proposals, gt)
        if gt.key == merged_key:  # the chosen car's proposal also takes in its neighbour's upper half
            t = scene.objects
            row = int((t.instance_id == car).nonzero()[0])
            others = [r for r in range(len(t)) if r != row and int(t.mask[r].sum()) > 0.2 * int(t.mask[row].sum())]
            assert others, "the tiny synthetic frame needs a second car"
            other = t.mask[others[0]].bool()
            ys = other.any(1).nonzero().flatten()
            piece = other & (torch.arange(other.shape[0])[:, None] < int(ys.float().mean()))
            t.mask[row] = (t.mask[row].bool() | piece).to(t.mask.dtype)
        return scene

    monkeypatch.setattr(derendering, "derender", merging)
    chosen = _found_example(records, source, Models(textural="textural branch"), "cpu")
    assert chosen is None or (chosen[0].key, chosen[1]) != (merged_key, car)
