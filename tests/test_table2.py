"""``sdn3d-table2``: Table 2 from sdn3d-train run summaries."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import torch

from sdn3d.cli.table2 import PAPER, ROWS, build_table, latest_runs, main, render_markdown

CONF = Path(__file__).resolve().parents[1] / "conf"


def _run(ablation, finished, value, status="ok", branch="geometric", run_dir=None, **extra):
    metrics = {"test/orientation_similarity": 0.9 + value, "test/distance_error": value,
               "test/scale_error": 0.3 + value, "test/reprojection_error": value / 10, "val/distance_error": 9.0}
    return {"branch": branch, "ablation": ablation, "run_dir": run_dir or f"/runs/{ablation}/{finished}",
            "best_ckpt": None, "last_ckpt": None, "metrics": metrics if status == "ok" else {},
            "overrides": [f"ablation={ablation}"], "seed": 0, "wall_s": 1.0, "finished": finished,
            "status": status, **extra}


def _write_jsonl(path: Path, records) -> Path:
    path.write_text("".join(json.dumps(r) + "\n" for r in records))
    return path


def _table_rows(markdown: str) -> dict[str, list[str]]:
    rows = {}
    for line in markdown.splitlines():
        if line.startswith("| ") and not line.startswith("| Method"):
            cells = [c.strip() for c in line.strip("|").split("|")]
            rows[cells[0]] = cells[1:]
    return rows


RECORDS = [
    _run("full", "2026-11-22T10:00:00+00:00", 0.05),
    _run("full", "2026-11-22T12:00:00+00:00", 0.04),   # latest full run: this one
    _run("full", "2026-11-22T11:00:00+00:00", 0.06),
    _run("full", "2026-11-22T13:00:00+00:00", 0.0, status="failed"),  # failed runs never beat ok ones
    _run("no_reproj", "2026-11-22T09:00:00+00:00", 0.07),
    _run("no_tau", "2026-11-22T09:00:00+00:00", 0.0, status="failed"),
    _run(None, "2026-11-22T14:00:00+00:00", 0.01, branch="semantic"),
    _run("my_ablation", "2026-11-22T09:00:00+00:00", 0.02),
]


def test_latest_ok_run_per_ablation():
    runs = latest_runs(RECORDS)
    assert runs["full"]["metrics"]["test/distance_error"] == 0.04
    assert runs["no_tau"]["status"] == "failed"
    assert set(runs) == {"full", "no_reproj", "no_tau", "my_ablation"}
    # A geometric run without an ablation name is the default (full) model.
    runs = latest_runs([_run(None, "2026-11-22T15:00:00+00:00", 0.03)])
    assert set(runs) == {"full"}


def test_table_from_jsonl(tmp_path, capsys):
    summary = _write_jsonl(tmp_path / "summary.jsonl", RECORDS)
    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--out", str(out), "--deep3dbox", "skip"]) == 0
    markdown = (out / "table2.md").read_text()
    assert markdown == capsys.readouterr().out
    rows = _table_rows(markdown)
    labels = [label for _, label in ROWS]
    assert list(rows) == labels  # the paper's row order
    full = rows["full model"]
    assert full[:4] == ["0.940", "4.00e-2", "0.340", "4.00e-3"]
    assert full[4:] == ["0.987", "3.87e-2", "0.382", "3.37e-3"]  # the paper's full-model numbers
    assert rows["w/o reprojection"][:4] == ["0.970", "7.00e-2", "0.370", "7.00e-3"]
    assert rows["w/o tau (log distance)"][:4] == ["failed"] * 4
    assert rows["single CAD"][:4] == ["not run"] * 4 and rows["single CAD"][4:] == [""] * 4
    assert rows[labels[0]][:4] == ["not run"] * 4
    assert "my_ablation" in markdown  # reported as left out, not silently dropped

    table = json.loads((out / "table2.json").read_text())
    by_key = {row["key"]: row for row in table["rows"]}
    assert [row["key"] for row in table["rows"]] == [key for key, _ in ROWS]
    assert by_key["full"]["metrics"]["test/distance_error"] == 0.04
    assert by_key["full"]["source"]["run_dir"] == "/runs/full/2026-11-22T12:00:00+00:00"
    assert by_key["full"]["paper"] == PAPER["full"]
    assert by_key["single_cad"]["status"] == "not run" and by_key["no_tau"]["status"] == "failed"
    assert by_key["deep3dbox"]["note"].startswith("not evaluated")
    assert table["ignored_ablations"] == ["my_ablation"]


def test_multirun_directories_and_missing_metrics(tmp_path):
    multirun = tmp_path / "multirun"
    for i, ablation in enumerate(("single_cad", "full_quaternion")):
        run = multirun / f"{i}_ablation={ablation}"
        run.mkdir(parents=True)
        record = _run(ablation, f"2026-11-22T0{i}:00:00+00:00", 0.02 * (i + 1), run_dir=str(run))
        if ablation == "full_quaternion":
            del record["metrics"]["test/reprojection_error"]
        (run / "summary.json").write_text(json.dumps(record, indent=2))
    summary = _write_jsonl(tmp_path / "s.jsonl", [_run("single_cad", "2026-11-21T00:00:00+00:00", 0.5)])
    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--multirun", str(multirun), "--out", str(out),
                 "--deep3dbox", "skip"]) == 0
    rows = _table_rows((out / "table2.md").read_text())
    assert rows["single CAD"][1] == "2.00e-2"  # the multirun's run is later than the JSONL's
    assert rows["quaternion (4-D)"][:4] == ["0.940", "4.00e-2", "0.340", "n/a"]
    assert rows["full model"][:4] == ["not run"] * 4


@pytest.mark.parametrize("bad, message", [
    ('{"branch": "geometric", "ablation": "full", ', "s.jsonl:2: not valid JSON"),
    ('["not", "an", "object"]', "s.jsonl:2: expected a JSON object"),
    ('{"branch": "geometric", "status": "ok"}', "s.jsonl:2: missing key 'metrics'"),
    ('{"branch": "geometric", "status": "ok", "metrics": {"test/distance_error": "0.1"}}', "must be a number"),
    ('{"branch": "geometric", "status": "ok", "metrics": {}, "finished": "yesterday"}', "not an ISO time"),
])
def test_bad_line_exits_2_and_leaves_outputs(tmp_path, capsys, bad, message):
    summary = tmp_path / "s.jsonl"
    summary.write_text(json.dumps(RECORDS[0]) + "\n" + bad + "\n" + json.dumps(RECORDS[1]) + "\n")
    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--out", str(out), "--deep3dbox", "skip"]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()
    # Existing outputs are not touched either.
    out.mkdir()
    (out / "table2.md").write_text("old\n")
    assert main(["--summary", str(summary), "--out", str(out), "--deep3dbox", "skip"]) == 2
    assert (out / "table2.md").read_text() == "old\n" and sorted(p.name for p in out.iterdir()) == ["table2.md"]


def test_bad_multirun_file_and_missing_inputs(tmp_path, capsys):
    run = tmp_path / "multirun" / "0"
    run.mkdir(parents=True)
    (run / "summary.json").write_text('{\n  "branch": "geometric",\n  "status": ok\n}\n')
    assert main(["--multirun", str(tmp_path / "multirun"), "--out", str(tmp_path / "out")]) == 2
    assert f"{run / 'summary.json'}:3: not valid JSON" in capsys.readouterr().err
    assert main(["--summary", str(tmp_path / "nope.jsonl"), "--out", str(tmp_path / "out")]) == 2
    assert "does not exist" in capsys.readouterr().err
    assert main(["--out", str(tmp_path / "out")]) == 2
    assert not (tmp_path / "out").exists()


def test_deep3dbox_row_needs_a_full_checkpoint(tmp_path):
    summary = _write_jsonl(tmp_path / "s.jsonl", [_run("no_reproj", "2026-11-22T09:00:00+00:00", 0.07)])
    assert main(["--summary", str(summary), "--out", str(tmp_path / "out")]) == 0
    row = json.loads((tmp_path / "out" / "table2.json").read_text())["rows"][0]
    assert row["status"] == "not run" and "checkpoint" in row["note"]


def test_deep3dbox_row_from_a_checkpoint_and_oracle(tmp_path):
    """The full path: the full run's config.yaml (data) and checkpoint (GeometricPredictor)."""
    pytest.importorskip("sdn3d.geometric.predict")
    from omegaconf import OmegaConf

    from sdn3d.data.fixtures import write_vkitti1_fixture
    from sdn3d.geometric.model import GeometricNet

    data_root = tmp_path / "data"
    write_vkitti1_fixture(data_root, frames=range(5), size=(310, 94))
    run_dir = tmp_path / "runs" / "full"
    run_dir.mkdir(parents=True)
    data = OmegaConf.to_container(OmegaConf.load(CONF / "data" / "vkitti.yaml"))
    data.update(root="/elsewhere", image_size=[160, 64])
    config = {"data": data, "datamodule": {"_target_": "datamodules.GeometricDataModule", "data": data,
                                           "batch_size": 32, "crop_size": 32}}
    (run_dir / "config.yaml").write_text(OmegaConf.to_yaml(OmegaConf.create(config)))
    torch.manual_seed(0)
    net = GeometricNet()
    ckpt = run_dir / "best.ckpt"
    torch.save({"state_dict": {f"net.{k}": v for k, v in net.state_dict().items()},
                "hyper_parameters": {"rotation": "yaw_quaternion", "distance": "log_tau"}}, ckpt)
    record = _run("full", "2026-11-22T09:00:00+00:00", 0.05, run_dir=str(run_dir), best_ckpt=str(ckpt))
    summary = _write_jsonl(tmp_path / "s.jsonl", [record])

    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--out", str(out), "--data-root", str(data_root),
                 "--batch-size", "4"]) == 0
    row = json.loads((out / "table2.json").read_text())["rows"][0]
    assert row["status"] == "ok" and row["source"]["checkpoint"] == str(ckpt)
    assert all(v is not None for v in row["metrics"].values())
    assert row["extra"]["count"] > 0

    assert main(["--summary", str(summary), "--out", str(out), "--data-root", str(data_root),
                 "--deep3dbox", "oracle"]) == 0
    table = json.loads((out / "table2.json").read_text())
    row = table["rows"][0]
    assert row["label"].endswith("(oracle)") and row["metrics"]["test/orientation_similarity"] == pytest.approx(1.0)
    assert row["metrics"]["test/scale_error"] == pytest.approx(0.0, abs=1e-6)
    assert _table_rows(render_markdown(table))[row["label"]][0] == "1.000"

    # A broken checkpoint is an evaluation failure (exit 1), outputs stay as they were.
    ckpt.write_bytes(b"not a checkpoint")
    before = (out / "table2.json").read_text()
    assert main(["--summary", str(summary), "--out", str(out), "--data-root", str(data_root)]) == 1
    assert (out / "table2.json").read_text() == before


def test_build_table_without_runs():
    table = build_table({}, None)
    assert all(row["status"] == "not run" for row in table["rows"])
    assert "not run" in render_markdown(table)
