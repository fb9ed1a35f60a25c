"""Warnings on a weak semantic branch name the run, the figure and its value, and blame "real photos" only where
the input is not from the data that run trained on (sdn3d.runs.quality_warnings)."""

from __future__ import annotations

import json

import pytest

from sdn3d.runs import from_trained_data, quality_warnings, recorded_pq, trained_data


def _run(tmp_path, metrics, root, name="semantic", step=12):
    """A sdn3d-train-like run: summary.json (experiment, steps, metrics) + the resolved config.yaml's data."""
    run = tmp_path / name
    run.mkdir()
    (run / "summary.json").write_text(json.dumps({"branch": "semantic", "experiment": "demo_short",
                                                  "global_step": step, "metrics": metrics}))
    (run / "config.yaml").write_text(f"data:\n  kind: vkitti1\n  root: {root}\n  image_size: [312, 96]\n")
    return run / "summary.json"


def test_recorded_pq_reads_the_vehicle_classes_in_any_case():
    # sdn3d-train writes val/pq_Car (the class name's case): the vehicle classes' mean, not the all-things val/pq
    assert recorded_pq({"val/pq": 0.9, "val/pq_Car": 0.1, "val/pq_Van": 0.2, "val/pq_Pole": 0.0}) == \
        ("vehicle PQ", recorded_pq({"val/pq_car": 0.1, "val/pq_van": 0.2})[1])
    assert abs(recorded_pq({"val/pq_Car": 0.1, "val/pq_Van": 0.2})[1] - 0.15) < 1e-9
    assert recorded_pq({"val/pq": 0.4}) == ("val/pq", 0.4)
    assert recorded_pq({"test/pq_Car": 0.5, "val/pq_Car": 0.1}, "test") == ("vehicle PQ", 0.5)
    assert recorded_pq({"val/pq": float("nan")}) is None and recorded_pq(None) is None


def test_trained_data_and_whether_an_input_is_from_it(tmp_path):
    data = tmp_path / "data"
    (data / "vkitti_1.3.1_rgb" / "0001" / "clone").mkdir(parents=True)
    summary = _run(tmp_path, {}, data)
    trained = trained_data(summary)
    assert trained == {"kind": "vkitti1", "root": str(data.resolve())}
    assert from_trained_data(trained, data) is True  # a frame read from that dataset root
    assert from_trained_data(trained, data / "vkitti_1.3.1_rgb" / "0001" / "clone" / "00003.png") is True
    assert from_trained_data(trained, tmp_path / "street.png") is False
    assert from_trained_data(trained, tmp_path / "data_other") is False  # a sibling whose name starts alike
    assert from_trained_data(trained, None) is None and from_trained_data(None, data) is None
    (summary.parent / "config.yaml").write_text("data:\n  root: ${oc.env:VKITTI_ROOT,data/vkitti}\n")
    assert trained_data(summary) is None  # unresolved: not known
    assert trained_data(tmp_path / "nowhere" / "summary.json") is None


def test_low_semantic_quality_names_the_run_the_figure_and_the_real_cause(tmp_path):
    data = tmp_path / "data"
    data.mkdir()
    summary = _run(tmp_path, {"val/pq": 0.0, "val/pq_Car": 0.0, "val/pq_Van": 0.0, "val/miou": 0.098}, data)
    metrics = json.loads(summary.read_text())["metrics"]
    run = f"run {summary.parent} (experiment demo_short, 12 training steps)"

    # the demo's own frame: the branch is weak on its own data; no word about real photos
    [own] = quality_warnings(metrics, None, str(summary), data)
    assert own.startswith(f"the semantic branch's recorded vehicle PQ is 0.000 (< 0.3, {summary}): {run} scored it "
                          "on its validation part")
    assert "is from the data the run trained on" in own and "train it longer" in own
    assert "real photos" not in own and "Virtual KITTI or Cityscapes" not in own

    # a photo from elsewhere: that is when real photos need other weights
    [photo] = quality_warnings(metrics, None, str(summary), tmp_path / "street.png")
    assert run in photo and f"not from the data the run trained on (vkitti1 at {data.resolve()})" in photo
    assert "real photos need branches trained on Virtual KITTI or Cityscapes" in photo

    # the input not known (a caller that does not say): the run and figure, no claim about the input
    [unknown] = quality_warnings(metrics, None, str(summary))
    assert run in unknown and "real photos" not in unknown and "proposals=boxes" in unknown

    # mIoU alone recorded; proposals over half the frame: both name the run
    [miou] = quality_warnings({"val/miou": 0.12}, None, str(summary), data)
    assert "recorded val/miou is 0.120 (< 0.3" in miou and run in miou and "real photos" not in miou
    [cover] = quality_warnings({"val/pq_Car": 0.8}, 0.73, str(summary), tmp_path / "street.png")
    assert f"proposals cover 73 % of the frame (> 50 %): not plausible vehicles ({run})" in cover
    assert "real photos need" in cover
    assert quality_warnings({"val/pq_Car": 0.8, "val/miou": 0.1}, 0.2, str(summary), data) == []


def test_the_demo_says_its_own_frames_are_from_its_training_data(tmp_path):
    """sdn3d-demo edits a frame of the data its semantic branch trained on: the reason it falls back to the
    ground truth names the run and the figure, and does not blame real photos."""
    from sdn3d.cli.demo import _semantic_distrust

    data = tmp_path / "data"
    data.mkdir()
    summary = _run(tmp_path, {"val/pq_Car": 0.0, "val/pq_Van": 0.0}, data)
    (summary.parent / "checkpoints").mkdir()
    [why] = _semantic_distrust(str(summary.parent / "checkpoints" / "best.ckpt"), data)
    assert "vehicle PQ is 0.000" in why and str(summary.parent) in why and "real photos" not in why
    assert _semantic_distrust(None, data) == []


def test_grabcut_is_seeded_by_a_trusted_semantic_branch_only_on_the_data_it_trained_on(tmp_path):
    """box_objects.prior auto: the semantic branch's vehicle probability seeds GrabCut where its recorded proposals
    are trusted and the input is a frame of its training data; never on a photo (a synthetic-trained branch there is
    no seed) nor with a weak branch."""
    from sdn3d.cli._config import compose_config
    from sdn3d.editing.settings import box_settings

    data = tmp_path / "data"
    data.mkdir()
    checkpoints = {}
    for name, recall in (("good", 0.8), ("weak", 0.2)):
        summary = _run(tmp_path, {"val/proposal_recall": recall, "val/proposal_precision": 0.7}, data, name)
        ckpt = summary.parent / "checkpoints" / "best.ckpt"
        ckpt.parent.mkdir()
        ckpt.write_bytes(b"")
        checkpoints[name] = {"semantic": {"path": str(ckpt), "from": "checkpoints.semantic"}}
    photo = compose_config([f"input.image={tmp_path / 'street.png'}"], "edit")
    frame = compose_config(["data=synth", f"data.root={data}", "input.frame=0"], "edit")
    assert box_settings(frame, checkpoints["good"])[1] is True
    assert box_settings(photo, checkpoints["good"])[1] is False
    assert box_settings(frame, checkpoints["weak"])[1] is False
    assert box_settings(compose_config(["data=synth", f"data.root={data}", "input.frame=0", "box_objects.prior=true"],
                                        "edit"),
                         checkpoints["weak"])[1] is True  # asked for: as asked


def test_a_runs_config_is_read_with_the_one_yaml_loader(tmp_path, monkeypatch):
    # sdn3d-edit reads the semantic run's config.yaml once a call (box_objects.prior auto): with libyaml's parser
    # where PyYAML has it (sdn3d.io.yaml_loader: 11 ms -> 1 ms for a run's 170 lines), the same data
    import yaml

    from sdn3d.io import yaml_loader

    assert yaml_loader() is getattr(yaml, "CSafeLoader", yaml.SafeLoader)
    summary = _run(tmp_path, {}, tmp_path / "data")
    used, real_load = [], yaml.load

    def load(stream, Loader):  # noqa: N803 (yaml's name)
        used.append(Loader)
        return real_load(stream, Loader=Loader)  # noqa: S506 (the loader is a safe one, checked below)

    monkeypatch.setattr(yaml, "load", load)
    monkeypatch.setattr(yaml, "safe_load", lambda stream: pytest.fail("the pure-Python safe_load was used"))
    assert trained_data(summary) == {"kind": "vkitti1", "root": str((tmp_path / "data").resolve())}
    assert used == [yaml_loader()] and issubclass(used[0], (yaml.SafeLoader, getattr(yaml, "CSafeLoader", ())))
    (summary.parent / "config.yaml").write_text("data: [unclosed\n")
    assert trained_data(summary) is None  # invalid YAML: not recorded, as before



def test_a_runs_config_is_read_only_for_a_warnings_advice(tmp_path, monkeypatch):
    """quality_warnings reads the run's config.yaml (where the data it trained on lies) only to advise on a warning
    it gives: a trusted branch's call reads nothing, and each warning's advice still says whether the input is from
    that data (main read the file on every call, warning or not: two of sdn3d-edit's three reads)."""
    import yaml

    data = tmp_path / "data"
    trusted = {"val/proposal_recall": 0.8, "val/proposal_precision": 0.7}
    weak = {"val/proposal_recall": 0.2, "val/proposal_precision": 0.7}
    good_run, weak_run = _run(tmp_path, trusted, data, "good"), _run(tmp_path, weak, data, "weak")
    reads, real_load = [], yaml.load

    def load(stream, Loader):  # noqa: N803 (yaml's name)
        reads.append(Loader)
        return real_load(stream, Loader=Loader)  # noqa: S506 (sdn3d.io.yaml_loader's safe loader)

    monkeypatch.setattr(yaml, "load", load)
    assert quality_warnings(trusted, 0.2, str(good_run), input_path=data / "0001") == []
    assert quality_warnings(trusted, None, str(good_run), input_path=tmp_path / "street.png") == []
    assert reads == []
    warned = quality_warnings(weak, None, str(weak_run), input_path=data / "0001")
    assert len(warned) == 1 and f"this input is from the data the run trained on ({data.resolve()})" in warned[0]
    assert len(reads) == 1
    covered = quality_warnings(trusted, 0.9, str(good_run), input_path=tmp_path / "street.png")
    assert len(covered) == 1 and "this input is not from the data the run trained on (vkitti1 at" in covered[0]
    assert len(reads) == 2
