"""``sdn3d-table2``: Table 2 from sdn3d-train run summaries (grouped over seeds, the paper's six rows)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from sdn3d.cli.table2 import PAPER, ROWS, build_table, group_runs, main, render_markdown, summarize

LABELS = dict(ROWS)


def _run(ablation, finished, value, status="ok", branch="geometric", run_dir=None, seed=0, experiment="table2",
         overrides=(), **extra):
    metrics = {"test/orientation_similarity": 0.9 + value, "test/distance_error": value,
               "test/scale_error": 0.3 + value, "test/reprojection_error_image": value / 10,
               "test/reprojection_error_crop_soft": value + 0.05, "test/mesh_accuracy": 0.2 + value,
               "test/mesh_majority_floor": 0.21, "test/mesh_uniform_floor": 0.125,
               "test/mesh_identifiability_ceiling": 0.4, "test/selection_regret": value / 100,
               "val/distance_error": 9.0}
    return {"branch": branch, "ablation": ablation, "experiment": experiment,
            "run_dir": run_dir or f"/runs/{ablation}/{seed}/{finished}", "best_ckpt": None, "last_ckpt": None,
            "metrics": metrics if status == "ok" else {}, "seed": seed,
            "overrides": [f"ablation={ablation}", f"seed={seed}", "threads=2", *overrides], "wall_s": 1.0,
            "finished": finished, "status": status, **extra}


def _write_jsonl(path: Path, records) -> Path:
    path.write_text("".join(json.dumps(r) + "\n" for r in records))
    return path


def _tables(markdown: str) -> list[dict[str, list[str]]]:
    """Each markdown table as {method: cells after the method}."""
    tables: list[dict[str, list[str]]] = []
    for line in markdown.splitlines():
        if line.startswith("| Method"):
            tables.append({"header": [c.strip() for c in line.strip("|").split("|")][1:]})
        elif line.startswith("| ") and tables:
            cells = [c.strip() for c in line.strip("|").split("|")]
            tables[-1][cells[0]] = cells[1:]
    return tables


def _t(hour: int) -> str:
    return f"2026-11-22T{hour:02d}:00:00+00:00"


RECORDS = [
    _run("full", _t(10), 0.05, seed=0),
    _run("full", _t(11), 0.03, seed=1),
    _run("full", _t(9), 0.04, seed=2),
    _run("full", _t(12), 0.04, seed=0),  # a re-run of seed 0: replaces the 10:00 run
    _run("full", _t(13), 0.0, status="failed", seed=3),  # left out of the mean, counted
    _run("no_reproj", _t(9), 0.07),
    _run("no_tau", _t(9), 0.0, status="failed"),
    _run(None, _t(14), 0.01, branch="semantic"),
    _run("my_ablation", _t(9), 0.02),
    _run("full", _t(8), 0.5, experiment="demo"),  # another experiment: another table
]


def test_runs_grouped_by_experiment_and_ablation_one_per_seed():
    groups = group_runs(RECORDS)
    assert set(groups) == {"table2", "demo"}
    assert set(groups["table2"]) == {"full", "no_reproj", "no_tau", "my_ablation"}
    full = groups["table2"]["full"]
    assert sorted((r["seed"], r["status"]) for r in full) == [(0, "ok"), (1, "ok"), (2, "ok"), (3, "failed")]
    assert next(r for r in full if r["seed"] == 0)["finished"] == _t(12)
    # A geometric run without an ablation name is the default (full) model.
    assert set(group_runs([_run(None, _t(15), 0.03)])["table2"]) == {"full"}


def test_mean_and_sample_std_over_seeds(tmp_path, capsys):
    summary = _write_jsonl(tmp_path / "summary.jsonl", RECORDS)
    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--out", str(out)]) == 0
    markdown = (out / "table2.md").read_text()
    assert markdown == capsys.readouterr().out
    table2, mesh = _tables(markdown)
    assert [k for k in table2 if k != "header"] == [label for _, label in ROWS]  # the paper's row order
    full = table2[LABELS["full"]]
    # distance 0.04, 0.03, 0.04 -> mean 0.03667, sample std 0.00577; shown x1e-2
    assert full[:4] == ["3", "0.937 ± 0.006", "3.67 ± 0.58", "0.337 ± 0.006"]
    assert full[4] == "3.67 ± 0.58"  # reprojection x1e-3: value / 10
    assert table2[LABELS["no_reproj"]][:3] == ["1", "0.970", "7.00"]  # one run: no spread
    assert table2[LABELS["no_tau"]][1:6] == ["failed"] * 5
    assert table2[LABELS["single_cad"]][1:6] == ["not run"] * 5
    assert "full model" not in markdown and "1 failed run(s) left out" in markdown
    assert "my_ablation" in markdown and "demo" in markdown  # reported as left out, not silently dropped
    assert mesh[LABELS["full"]] == ["3", "0.237 ± 0.006", "0.210 ± 0.000", "0.125 ± 0.000", "0.400 ± 0.000",
                                    "0.0004 ± 0.0001"]

    table = json.loads((out / "table2.json").read_text())
    assert table["experiment"] == "table2" and table["other_experiments"] == ["demo"]
    by_key = {row["key"]: row for row in table["rows"]}
    dist = by_key["full"]["metrics"]["test/distance_error"]
    assert dist["n"] == 3 and dist["mean"] == pytest.approx(0.11 / 3)
    assert dist["std"] == pytest.approx(0.005773502, rel=1e-6) and sorted(dist["values"]) == [0.03, 0.04, 0.04]
    assert sorted(by_key["full"]["seeds"]) == [0, 1, 2] and by_key["full"]["failed"] == 1
    assert table["ignored_ablations"] == ["my_ablation"]


def test_the_six_reference_rows_of_the_paper(tmp_path):
    assert [key for key, _ in ROWS] == list(PAPER)
    table = build_table({}, None)
    markdown = render_markdown(table)
    rows = _tables(markdown)[0]
    header = rows["header"]
    assert header[-4:] == ["paper: orientation", "paper: distance (x1e-2)", "paper: scale (m)",
                           "paper: reprojection (x1e-3, per image pixel)"]
    expected = {
        "Mousavian et al. (Deep3DBox)": ["0.976", "4.41", "0.391", "9.80"],
        "w/o L_reproj": ["0.980", "3.76", "0.372", "9.54"],
        "w/o quaternion constraint": ["0.970", "4.59", "0.403", "7.58"],
        "w/o normalized distance tau": ["0.979", "4.27", "0.420", "6.42"],
        "w/o MultiCAD and FFD": ["0.984", "3.37", "0.464", "4.60"],
        "3D-SDN (full)": ["0.987", "3.87", "0.382", "3.37"],
    }
    for label, values in expected.items():
        assert rows[label][-4:] == values and rows[label][1:6] == ["not run"] * 5
    assert PAPER["full"]["test/reprojection_error_image"] == 3.37e-3 and PAPER["deep3dbox"]["test/distance_error"] \
        == 4.41e-2


def test_units_and_frame_size_in_the_header(tmp_path):
    run_dir = tmp_path / "runs" / "full"
    run_dir.mkdir(parents=True)
    (run_dir / "config.yaml").write_text("data:\n  image_size: [624, 192]\ndatamodule:\n  crop_size: 64\n")
    summary = _write_jsonl(tmp_path / "s.jsonl", [_run("full", _t(9), 0.04, run_dir=str(run_dir))])
    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--out", str(out)]) == 0
    markdown = (out / "table2.md").read_text()
    header = _tables(markdown)[0]["header"]
    assert header[:6] == ["n", "Orientation similarity ↑", "Distance error (x1e-2) ↓", "Scale error (m) ↓",
                          "Reprojection error (x1e-3; hard, per pixel of the 624x192 frame) ↓",
                          "Soft crop mean (64-px crops; training loss, not the paper's) ↓"]
    assert "frame 624x192 (W x H, the working size" in markdown
    table = json.loads((out / "table2.json").read_text())
    assert table["frame_size"] == [624, 192] and table["crop_size"] == 64
    assert table["columns"][3]["scale"] == 1e3 and table["columns"][1]["scale"] == 1e2


def test_runs_that_differ_in_more_than_the_seed_are_reported(tmp_path, capsys):
    records = [_run("full", _t(9), 0.04, seed=0, overrides=["data.root=/a"]),
               _run("full", _t(10), 0.05, seed=1, overrides=["data.root=/b"]),
               _run("no_tau", _t(9), 0.04, seed=0, overrides=["data.root=/a", "trainer.enable_progress_bar=False"]),
               _run("no_tau", _t(10), 0.05, seed=1, overrides=["data.root=/a"])]
    summary = _write_jsonl(tmp_path / "s.jsonl", records)
    assert main(["--summary", str(summary), "--out", str(tmp_path / "out")]) == 0
    captured = capsys.readouterr()
    assert "warning: 3D-SDN (full): its 2 runs differ in more than the seed: data.root=/a; data.root=/b" \
        in captured.err
    assert "warning: 3D-SDN (full)" in captured.out and "w/o normalized distance tau: its" not in captured.err
    table = json.loads((tmp_path / "out" / "table2.json").read_text())
    assert len(table["warnings"]) == 1


def test_experiment_choice(tmp_path, capsys):
    summary = _write_jsonl(tmp_path / "s.jsonl", RECORDS)
    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--out", str(out), "--experiment", "demo"]) == 0
    table = json.loads((out / "table2.json").read_text())
    assert table["experiment"] == "demo" and table["other_experiments"] == ["table2"]
    full = next(row for row in table["rows"] if row["key"] == "full")
    assert full["n"] == 1 and full["metrics"]["test/distance_error"]["mean"] == 0.5
    capsys.readouterr()
    assert main(["--summary", str(summary), "--out", str(out), "--experiment", "paper"]) == 2
    assert "--experiment 'paper': no geometric run of that experiment" in capsys.readouterr().err
    # Runs recorded without an experiment are 'none'.
    summary = _write_jsonl(tmp_path / "n.jsonl", [_run("full", _t(9), 0.04, experiment=None)])
    assert main(["--summary", str(summary), "--out", str(out), "--experiment", "none"]) == 0


def test_summarize():
    assert summarize([]) is None
    assert summarize([2.0]) == {"mean": 2.0, "std": None, "n": 1, "values": [2.0]}
    assert summarize([1.0, 3.0])["std"] == pytest.approx(2 ** 0.5)


def test_multirun_directories_and_missing_metrics(tmp_path):
    multirun = tmp_path / "multirun"
    for i, ablation in enumerate(("single_cad", "full_quaternion")):
        run = multirun / f"{i}_ablation={ablation}"
        run.mkdir(parents=True)
        record = _run(ablation, _t(i), 0.02 * (i + 1), run_dir=str(run))
        if ablation == "full_quaternion":
            del record["metrics"]["test/reprojection_error_image"]
        (run / "summary.json").write_text(json.dumps(record, indent=2))
    summary = _write_jsonl(tmp_path / "s.jsonl", [_run("single_cad", "2026-11-21T00:00:00+00:00", 0.5)])
    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--multirun", str(multirun), "--out", str(out)]) == 0
    rows = _tables((out / "table2.md").read_text())[0]
    assert rows[LABELS["single_cad"]][2] == "2.00"  # the multirun's run is later than the JSONL's (same seed)
    assert rows[LABELS["full_quaternion"]][1:5] == ["0.940", "4.00", "0.340", "n/a"]
    assert rows[LABELS["full"]][1:6] == ["not run"] * 5


@pytest.mark.parametrize("bad, message", [
    ('{"branch": "geometric", "ablation": "full", ', "s.jsonl:2: not valid JSON"),
    ('["not", "an", "object"]', "s.jsonl:2: expected a JSON object"),
    ('{"branch": "geometric", "status": "ok"}', "s.jsonl:2: missing key 'metrics'"),
    ('{"branch": "geometric", "status": "ok", "metrics": {"test/distance_error": "0.1"}}', "must be a number"),
    ('{"branch": "geometric", "status": "ok", "metrics": {}, "finished": "yesterday"}', "not an ISO time"),
    ('{"branch": "geometric", "status": "ok", "metrics": {}, "seed": "1"}', "'seed' must be an integer"),
])
def test_bad_line_exits_2_and_leaves_outputs(tmp_path, capsys, bad, message):
    summary = tmp_path / "s.jsonl"
    summary.write_text(json.dumps(RECORDS[0]) + "\n" + bad + "\n" + json.dumps(RECORDS[1]) + "\n")
    out = tmp_path / "out"
    assert main(["--summary", str(summary), "--out", str(out)]) == 2
    assert message in capsys.readouterr().err
    assert not out.exists()
    # Existing outputs are not touched either.
    out.mkdir()
    (out / "table2.md").write_text("old\n")
    assert main(["--summary", str(summary), "--out", str(out)]) == 2
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


def test_build_table_without_runs():
    table = build_table({}, None)
    assert all(row["status"] == "not run" and row["n"] == 0 for row in table["rows"])
    assert "not run" in render_markdown(table) and table["frame_size"] is None


def test_sources_say_which_checkpoint_the_test_figures_come_from():
    runs = [_run("full", "2026-11-24T09:00:00+00:00", 0.05, tested_checkpoint="best",
                 selected_by="val/reprojection_error_image (min) on the validation part"),
            _run("no_reproj", "2026-11-24T09:00:00+00:00", 0.05, tested_checkpoint="final"),
            _run("single_cad", "2026-11-22T09:00:00+00:00", 0.05)]
    markdown = render_markdown(build_table(group_runs(runs), "table2"))
    assert "test figures from the checkpoint selected by val/reprojection_error_image (min) on the validation part" \
        in markdown
    assert "test figures from the weights at the end of fitting" in markdown
    assert "test figures from tested weights not recorded (a run from before 2026-11-24" in markdown


def _with(record, **metrics):
    record["metrics"].update(metrics)
    return record


def test_paired_differences_with_a_student_t_interval(tmp_path):
    """Rows are paired with the full model by seed; the interval is mean ± t(0.975, n-1) sd / sqrt(n)."""
    full = [_run("full", _t(9), v, seed=s) for s, v in enumerate((0.04, 0.05, 0.06))]
    no_reproj = [_run("no_reproj", _t(9), v, seed=s) for s, v in enumerate((0.05, 0.07, 0.08, 0.5))]  # seed 3 unpaired
    table = build_table(group_runs(full + no_reproj), "table2")
    (entry,) = [p for p in table["paired"] if p["key"] == "no_reproj"]
    reproj = entry["differences"]["test/reprojection_error_image"]  # value / 10: diffs 0.001, 0.002, 0.002
    assert reproj["seeds"] == [0, 1, 2] and reproj["n"] == 3
    assert reproj["mean"] == pytest.approx(0.005 / 3)
    half = 4.302652729911275 * 0.000577350269 / 3 ** 0.5  # t(0.975, 2) sd / sqrt(3)
    assert reproj["low"] == pytest.approx(0.005 / 3 - half, rel=1e-6)
    assert reproj["high"] == pytest.approx(0.005 / 3 + half, rel=1e-6)
    # full is lower by mean(diff) / mean(no_reproj over the paired seeds) = (0.005/3) / (0.02/3) = 25 %
    assert reproj["full_lower"]["mean"] == pytest.approx(0.25)
    markdown = render_markdown(table)
    assert "## Paired with 3D-SDN (full)" in markdown
    line = next(li for li in markdown.splitlines() if li.startswith("| w/o L_reproj | 0,1,2"))
    assert "| 25 % [" in line and "+1.667 [" in line


def test_variants_get_their_own_rows_and_the_test_time_fit_a_row(tmp_path):
    refined = {"test/refined/orientation_similarity": 0.99, "test/refined/distance_error": 0.02,
               "test/refined/scale_error": 0.2, "test/refined/reprojection_error_image": 0.001}
    records = [_with(_run("full", _t(9), 0.04, seed=s), **refined) for s in (0, 1)]
    records += [_run("full", _t(9), 0.06, seed=s, variant="soft_silhouette",
                     overrides=["model.reproj_silhouette=soft"]) for s in (0, 1)]
    table = build_table(group_runs(records), "table2")
    keys = [row["key"] for row in table["rows"]]
    assert keys.index("full") < keys.index("full:soft_silhouette") < keys.index("full+refined")
    rows = {row["key"]: row for row in table["rows"]}
    assert rows["full:soft_silhouette"]["label"] == "3D-SDN (full), soft_silhouette"
    assert "warning" not in rows["full"] and not table["warnings"] and not table["ignored_ablations"]
    assert rows["full+refined"]["metrics"]["test/reprojection_error_image"]["mean"] == pytest.approx(0.001)
    paired = {p["key"]: p for p in table["paired"]}
    assert paired["full:soft_silhouette"]["differences"]["test/distance_error"]["mean"] == pytest.approx(0.02)
    assert paired["full+refined"]["differences"]["test/scale_error"]["mean"] == pytest.approx(0.2 - 0.34)
    tables = _tables(render_markdown(table))
    assert "3D-SDN (full) + test-time fit (Adam 0.03 x 16)" in tables[0]


def test_decomposition_shares(tmp_path):
    parts = {"predicted": 6.0, "chosen_no_ffd": 6.5, "sedan": 7.0, "true_template": 5.0,
             "true_template_no_ffd": 5.5, "best_of_8": 4.0, "truth_pose_true_template": 1.0}
    records = [_with(_run("full", _t(9), 0.04, seed=s),
                     **{f"test/decomposition/{k}": (v + s) * 1e-3 for k, v in parts.items()}) for s in (0, 1)]
    table = build_table(group_runs(records), "table2")
    (entry,) = table["decomposition"]
    assert entry["n"] == 2 and entry["values"]["predicted"]["mean"] == pytest.approx(6.5e-3)
    shares = entry["shares"]
    assert shares["floor"] == pytest.approx(1.5e-3) and shares["pose"] == pytest.approx(4.5e-3)
    assert shares["mesh_choice"] == pytest.approx(1e-3) and shares["ffd"] == pytest.approx(-0.5e-3)
    assert shares["selection_room"] == pytest.approx(2e-3)
    markdown = render_markdown(table)
    assert "## Where the reprojection error comes from" in markdown and "| 3D-SDN (full) | 1.50 (23 %) |" in markdown


def test_the_multibin_row_follows_the_paper_rows_only_when_run_and_is_paired_with_full():
    full = [_run("full", _t(9), v, seed=s) for s, v in enumerate((0.04, 0.05))]
    multibin = [_run("full_multibin", _t(9), v, seed=s) for s, v in enumerate((0.02, 0.03))]
    without = build_table(group_runs(full), "table2")
    assert "full_multibin" not in [row["key"] for row in without["rows"]]
    table = build_table(group_runs(full + multibin), "table2")
    keys = [row["key"] for row in table["rows"]]
    assert keys[-1] == "full_multibin" and keys.index("full") < keys.index("full_multibin")
    assert not table["ignored_ablations"]
    paired = {p["key"]: p for p in table["paired"]}
    assert paired["full_multibin"]["differences"]["test/distance_error"]["mean"] == pytest.approx(-0.02)
    label = "3D-SDN (full), MultiBin orientation (the editing default; not a paper row)"
    assert _tables(render_markdown(table))[0][label][:2] == ["2", "0.925 ± 0.007"]


def test_fit_gap_reports_test_over_train_l_pred_per_run():
    records = [_with(_run("full", _t(9), 0.04, seed=s), **{"train/loss_pred": train, "test/loss_pred": test})
               for s, (train, test) in enumerate(((0.1, 0.3), (0.2, 0.2)))]
    records.append(_run("no_reproj", _t(9), 0.05))  # no L_pred logged: no entry
    table = build_table(group_runs(records), "table2")
    (entry,) = table["fit_gap"]
    assert entry["key"] == "full" and entry["n"] == 2
    assert entry["ratio"]["mean"] == pytest.approx(2.0) and sorted(entry["ratio"]["values"]) == pytest.approx([1, 3])
    assert entry["train"]["mean"] == pytest.approx(0.15) and entry["test"]["mean"] == pytest.approx(0.25)
    markdown = render_markdown(table)
    assert "## Over-fitting: L_pred on the training and the test part" in markdown
    assert "| 3D-SDN (full) | 2 | 0.1500 ± 0.0707 | 0.2500 ± 0.0707 | 2.00 ± 1.41 |" in markdown
