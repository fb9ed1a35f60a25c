"""The 3D-SDN edit benchmark format: the shipped files, round trips, scaling, validation."""

from __future__ import annotations

import hashlib
import json
import math
import sys
from collections import Counter
from pathlib import Path

import pytest
import torch

from sdn3d.data.edit_benchmark import (
    BenchmarkEntry,
    BenchmarkOperation,
    benchmark_path,
    load_edit_benchmark,
    save_edit_benchmark,
    scale_entry,
    scale_operation,
    scale_point,
    validate_in_frame,
)
from sdn3d.data.errors import DataFormatError
from sdn3d.math3d.camera import VKITTI_INTRINSICS, project_points
from sdn3d.resources import PAPER_LICENSE, paper_benchmark_path, paper_example_path, resource_path


@pytest.fixture(scope="module")
def benchmark():
    return load_edit_benchmark(paper_benchmark_path())


def test_shipped_benchmark_counts(benchmark):
    assert len(benchmark) == 184
    real, identity = benchmark[:92], benchmark[92:]
    assert all(e.operations for e in real) and all(e.is_identity for e in identity)
    ops = [op for e in benchmark for op in e.operations]
    assert len(ops) == 424
    assert Counter(op.kind for op in ops) == {"modify": 393, "delete": 31}
    # Identity entries repeat each real entry's source frame as its own target.
    for edit, same in zip(real, identity, strict=True):
        assert (same.world, same.variation) == (edit.world, edit.variation)
        assert same.source_frame == edit.source_frame
        assert same.target_frame == same.source_frame
    assert {e.world for e in benchmark} <= {"0001", "0002", "0006", "0018", "0020"}


def test_shipped_benchmark_values(benchmark):
    first = benchmark[0]
    assert (first.world, first.variation, first.source_frame, first.target_frame) == ("0006", "fog", 55, 50)
    op = first.operations[0]
    assert op == BenchmarkOperation("modify", (750.9, 213.9), (804.4, 227.1), 1.338, 0.007, (194, 756, 269, 865))
    delete = first.operations[2]
    assert delete.kind == "delete" and delete.to_uv is None and delete.zoom is None and delete.ry is None
    # Deletes carry no target; every modify of the benchmark has a target point and an roi.
    ops = [op for e in benchmark for op in e.operations]
    assert all(op.to_uv is not None and op.roi is not None for op in ops if op.kind == "modify")
    assert all(op.zoom > 0 and math.isfinite(op.ry) for op in ops if op.kind == "modify")


def test_out_of_frame_points_load_but_fail_user_validation(benchmark):
    delete = benchmark[0].operations[2]
    assert delete.from_uv == (1328.5, 271.3)  # outside 1242x375, yet in the published file
    with pytest.raises(ValueError, match=r"entry 0 .*operation 2 \(delete\) 'from' point \(1328.5, 271.3\)"):
        validate_in_frame(benchmark[0], index=0)
    validate_in_frame(benchmark[0], margin=100.0)
    validate_in_frame(benchmark[1])
    outside = [i for i, e in enumerate(benchmark) if _fails(e)]
    assert 0 < len(outside) < 92 and all(i < 92 for i in outside)
    with pytest.raises(ValueError, match="margin"):
        validate_in_frame(benchmark[1], margin=-1)


def _fails(entry: BenchmarkEntry) -> bool:
    try:
        validate_in_frame(entry)
    except ValueError:
        return True
    return False


def test_example_file():
    entries = load_edit_benchmark(paper_example_path())
    assert [e.target_frame for e in entries] == [0, 1, 2, 3, 4]
    assert {(e.world, e.variation, e.source_frame) for e in entries} == {("0006", "30-deg-right", 43)}
    ops = [e.operations[0] for e in entries]
    assert all(op.kind == "modify" and op.to_uv is None and op.zoom == 1.0 for op in ops)
    assert all(op.from_uv == (552.0, 251.0) for op in ops)
    assert [op.ry for op in ops] == [0.0, 0.837758, 3.141593, 4.18879, 6.073746]


def test_round_trip_keeps_entries_and_format(benchmark, tmp_path):
    path = tmp_path / "out" / "bench.json"
    save_edit_benchmark(benchmark, path)
    assert load_edit_benchmark(path) == benchmark
    original = json.loads(paper_benchmark_path().read_text())
    saved = json.loads(path.read_text())
    assert _numbers_as_floats(saved) == _numbers_as_floats(original)
    # Numbers stay strings as in the published file; `to` null vs {} is kept.
    assert isinstance(saved[0]["operations"][0]["zoom"], str) and saved[0]["operations"][2]["to"] is None
    text = path.read_text()
    save_edit_benchmark(load_edit_benchmark(path), path)
    assert path.read_text() == text  # stable once written
    example = load_edit_benchmark(paper_example_path())
    save_edit_benchmark(example, path)
    assert json.loads(path.read_text())[0]["operations"][0]["to"] == {}
    assert load_edit_benchmark(path) == example


def _numbers_as_floats(node):
    if isinstance(node, dict):
        return {k: _numbers_as_floats(v) for k, v in node.items()}
    if isinstance(node, list):
        return [_numbers_as_floats(v) for v in node]
    if isinstance(node, str):
        try:
            return float(node)
        except ValueError:
            return node
    return float(node) if isinstance(node, int) else node


def test_shipped_files_are_package_data_with_their_licence():
    """The paper's files ship in sdn3d.resources, byte for byte, with the BSD licence they come under."""
    assert paper_benchmark_path().parent == Path(sys.modules[resource_path.__module__].__file__).parent
    assert benchmark_path("paper") == paper_benchmark_path()
    assert benchmark_path("paper_example") == paper_example_path()
    # Redistributed unchanged (the authors' release).
    assert hashlib.sha256(paper_benchmark_path().read_bytes()).hexdigest() == (
        "8cf4548f3add2991c833ec7bebab3559e6aa5f988d8be82f0d2d792a4da0bca0")
    assert hashlib.sha256(paper_example_path().read_bytes()).hexdigest() == (
        "35437c7cc9bdaa640836217b6da8ee907c07be45d2a28dd1fa166124abd9d377")
    licence = resource_path(PAPER_LICENSE).read_text()
    assert "Shunyu Yao" in licence and "Redistribution and use in source and binary forms" in licence
    assert benchmark_path("~/x.json") == Path.home() / "x.json" and benchmark_path("./paper") == Path("paper")
    with pytest.raises(ValueError, match="unknown sdn3d resource"):
        resource_path("nope.json")


def test_bench_cli_finds_the_shipped_paper_benchmark(tmp_path, capsys):
    """``sdn3d-bench benchmark=paper`` loads the shipped file: it gets past the benchmark to the checkpoints."""
    from sdn3d.cli.bench import main

    assert main(["benchmark=paper", f"output_dir={tmp_path / 'out'}"]) == 2
    err = capsys.readouterr().err
    assert "checkpoints.textural" in err and "benchmark" not in err, err
    assert main([f"benchmark={tmp_path / 'paper'}", f"output_dir={tmp_path / 'out'}"]) == 2
    assert "benchmark" in capsys.readouterr().err  # any other value is a path


def test_save_is_atomic(tmp_path, monkeypatch, benchmark):
    path = tmp_path / "bench.json"
    save_edit_benchmark(benchmark[:2], path)
    before = path.read_bytes()

    def boom(*args, **kwargs):
        raise RuntimeError("disk full")

    monkeypatch.setattr("sdn3d.io.os.replace", boom)
    with pytest.raises(RuntimeError):
        save_edit_benchmark(benchmark, path)
    assert path.read_bytes() == before
    assert [p.name for p in tmp_path.iterdir()] == ["bench.json"]


def _write(tmp_path, data) -> str:
    path = tmp_path / "edits.json"
    path.write_text(data if isinstance(data, str) else json.dumps(data))
    return str(path)


def _entry(**op):
    operation = {"type": "modify", "from": {"u": "10", "v": "20"}, "to": {}, "zoom": "1.0", "ry": "0.1"}
    operation.update(op)
    entry = {"world": "0001", "topic": "clone", "source": "00001", "target": "00002"}
    return {**entry, "operations": [operation]}


@pytest.mark.parametrize(
    ("data", "pattern"),
    [
        ("[{", r"invalid JSON at line 1"),
        ({"world": "0001"}, r"expected a JSON list"),
        ([_entry(), {"world": "0001", "source": "1", "target": "2", "operations": []}],
         r"entry 1: field 'topic': missing"),
        ([_entry(zoom="abc")], r"entry 0 operation 0: field 'zoom': expected a number, got 'abc'"),
        ([_entry(zoom="-1.5")], r"entry 0 operation 0: field 'zoom': expected a number > 0"),
        ([_entry(zoom="0")], r"field 'zoom': expected a number > 0"),
        ([_entry(zoom="nan")], r"field 'zoom': expected a finite number"),
        ([_entry(ry="inf")], r"field 'ry': expected a finite number"),
        # issue 42 (9): a finite but absurd yaw or zoom is refused too (ry 1e308 ran, every entry failing)
        ([_entry(ry="1e308")], r"field 'ry': expected a yaw increment in radians within \[-2 pi, 2 pi\], got '1e308'"),
        ([_entry(ry=-7)], r"field 'ry': expected a yaw increment"),
        ([_entry(zoom="1e308")], r"field 'zoom': expected a number <= 100"),
        ([_entry(zoom=None)], r"field 'zoom': expected a number or numeric string, got None"),
        ([_entry(type="move")], r"field 'type': expected one of"),
        ([_entry(**{"from": {"u": "1"}})], r"field 'from.v': missing"),
        ([_entry(to={"u": "1", "v": "2", "roi": [1, 2, 3]})], r"field 'to.roi': expected \[top, left"),
        ([_entry(to={"u": "1", "v": "2", "roi": [5, 2, 3, 4]})], r"field 'to.roi': expected top <= bottom"),
        ([_entry(zoom=True)], r"field 'zoom'"),
    ],
)  # fmt: skip
def test_malformed_inputs_name_path_entry_and_field(tmp_path, data, pattern):
    path = _write(tmp_path, data)
    with pytest.raises(ValueError, match=pattern) as info:
        load_edit_benchmark(path)
    assert isinstance(info.value, DataFormatError) and str(info.value).startswith(path)


def test_missing_file(tmp_path):
    with pytest.raises(FileNotFoundError, match="nope.json"):
        load_edit_benchmark(tmp_path / "nope.json")


def test_numbers_may_be_json_numbers(tmp_path):
    entry = _entry(zoom=1.25, ry=-0.5)
    entry["source"], entry["operations"][0]["from"] = 7, {"u": 3, "v": 4.5}
    (loaded,) = load_edit_benchmark(_write(tmp_path, [entry]))
    assert loaded.source_frame == 7
    assert loaded.operations[0] == BenchmarkOperation.modify((3, 4.5), zoom=1.25, ry=-0.5)


def test_scaling_matches_resized_intrinsics():
    working = VKITTI_INTRINSICS.resized(624, 192)
    # A 3D point projects, in both sizes, where scale_point maps its full-size pixel.
    points = torch.tensor([[1.0, 1.2, 10.0], [-4.0, 0.5, 25.0], [0.0, 0.0, 5.0]], dtype=torch.float64)
    full = project_points(points, VKITTI_INTRINSICS.matrix(torch.float64))
    small = project_points(points, working.matrix(torch.float64))
    for uv_full, uv_small in zip(full.tolist(), small.tolist(), strict=True):
        assert scale_point(uv_full, (1242, 375), (624, 192)) == pytest.approx(uv_small, abs=1e-9)
    # The principal point and the image corners map onto themselves.
    assert scale_point((620.5, 187.0), (1242, 375), (624, 192)) == pytest.approx((working.cx, working.cy))
    assert scale_point((-0.5, 374.5), (1242, 375), (624, 192)) == pytest.approx((-0.5, 191.5))


def test_scale_operation_and_back(benchmark):
    op = benchmark[0].operations[0]
    small = scale_operation(op)
    assert (small.kind, small.zoom, small.ry) == (op.kind, op.zoom, op.ry)
    top, left, bottom, right = small.roi
    assert left <= small.to_uv[0] <= right and top <= small.to_uv[1] <= bottom
    back = scale_operation(small, (624, 192), (1242, 375))
    assert back.from_uv == pytest.approx(op.from_uv) and back.roi == pytest.approx(op.roi)
    delete = scale_operation(benchmark[0].operations[2])
    assert delete.to_uv is None and delete.roi is None
    scaled = scale_entry(benchmark[0])
    assert scaled.operations[1] == scale_operation(benchmark[0].operations[1])
    with pytest.raises(ValueError, match="to_size"):
        scale_operation(op, to_size=(0, 192))


def test_operation_constructor_validation():
    assert BenchmarkOperation.delete((1, 2)).zoom is None
    with pytest.raises(ValueError, match="zoom must be > 0"):
        BenchmarkOperation.modify((1, 2), zoom=-1.0)
    with pytest.raises(ValueError, match="needs zoom and ry"):
        BenchmarkOperation("modify", (1, 2))
    with pytest.raises(ValueError, match="kind"):
        BenchmarkOperation("rotate", (1, 2))
    with pytest.raises(ValueError, match="finite"):
        BenchmarkOperation.modify((1, float("nan")))


# -- the YAML edit spec's number fields (sdn3d.editing.spec) ------------------------------------------


def test_yaml_spec_reads_numbers_pyyaml_leaves_as_strings(tmp_path):
    """Issue 20: PyYAML (YAML 1.1) reads ``1e9`` / ``1.0e9`` / ``5e-1`` as strings; they are numbers."""
    from sdn3d.editing.spec import load_edit_spec

    path = tmp_path / "ops.yaml"
    path.write_text("- {op: zoom, id: 12001, zoom: 1.0e9}\n- {op: zoom, id: 12002, zoom: 1e-9}\n"
                    "- {op: rotate, at: [1e2, 5E1], ry_rad: 5e-1}\n- {op: recolor, id: 12003, code: [1e-1, '2', 3]}\n"
                    "- {op: modify, from: ['10', 20], zoom: ' 2.5 ', ry_rad: -1e0}\n")
    ops = load_edit_spec(path).ops
    assert (ops[0].zoom, ops[1].zoom) == (1e9, 1e-9)
    assert ops[2].at == (100.0, 50.0) and ops[2].ry == 0.5 and ops[3].code == (0.1, 2.0, 3.0)
    assert ops[4].from_uv == (10.0, 20.0) and (ops[4].zoom, ops[4].ry) == (2.5, -1.0)


@pytest.mark.parametrize(("op", "pattern"), [
    ({"op": "zoom", "id": 12001, "zoom": "big"}, r"op 0 \(zoom\): field 'zoom' must be a number, got 'big'"),
    ({"op": "zoom", "id": 12001, "zoom": "1e9x"}, r"field 'zoom' must be a number, got '1e9x'"),
    ({"op": "zoom", "id": 12001, "zoom": ""}, r"field 'zoom' must be a number, got ''"),
    ({"op": "zoom", "id": 12001, "zoom": "nan"}, r"field 'zoom' must be finite"),
    ({"op": "zoom", "id": 12001, "zoom": "-1e0"}, r"field 'zoom' must be > 0"),
    ({"op": "rotate", "id": 12001, "ry_rad": "inf"}, r"field 'ry_rad' must be finite"),
    ({"op": "rotate", "id": 12001, "ry_deg": True}, r"field 'ry_deg' must be a number"),
    ({"op": "rotate", "id": 12001, "ry": 45}, r"field 'ry' has no unit: .*ry_deg .*ry_rad"),
    ({"op": "rotate", "id": 12001, "ry_rad": 45}, r"more than a full turn \(2 pi\): did you mean ry_deg: 45\?"),
    ({"op": "rotate", "id": 12001, "ry_rad": 0.5, "ry_deg": 30}, r"not both"),
    ({"op": "rotate", "id": 12001}, r"'ry_deg' \(degrees added to the yaw\) or 'ry_rad'"),
    ({"op": "move", "id": 12001, "to": ["left", 3]}, r"field 'to'\[0\] must be a number, got 'left'"),
    ({"op": "recolor", "id": 12001, "code": [0.1, "x"]}, r"field 'code\[1\]' must be a number, got 'x'"),
])  # fmt: skip
def test_yaml_spec_still_rejects_non_numbers_naming_the_field(op, pattern):
    from sdn3d.editing.spec import EditSpecError, parse_edit_spec

    with pytest.raises(EditSpecError, match=pattern):
        parse_edit_spec([op])


def test_angles_are_degrees_or_explicit_radians():
    from sdn3d.editing.spec import parse_edit_spec

    spec = parse_edit_spec([{"op": "rotate", "id": 12001, "ry_deg": 45}, {"op": "rotate", "id": 12001, "ry_rad": -0.5},
                            {"op": "modify", "from": [10, 20], "ry_deg": -90}])
    assert [round(op.ry, 12) for op in spec.ops] == [round(math.pi / 4, 12), -0.5, round(-math.pi / 2, 12)]



@pytest.mark.parametrize("op, pattern", [
    ({"op": "recolor", "id": 12001, "color": "chartreuse"}, r"op 0 \(recolor\): field 'color': unknown colour "
                                                              r"'chartreuse'; known colours: red"),
    ({"op": "recolor", "id": 12001, "color": 3}, r"field 'color' must be a colour name"),
    ({"op": "recolor", "id": 12001, "color": "red", "sample": True}, r"exactly one of 'code: \[...\]', 'sample: true' "
                                                                       r"or 'color: <name>'"),
    ({"op": "recolor", "id": 12001}, r"exactly one of"),
])  # fmt: skip
def test_recolor_by_colour_name_is_checked_when_parsed(op, pattern):
    from sdn3d.editing.spec import EditSpecError, parse_edit_spec

    with pytest.raises(EditSpecError, match=pattern):
        parse_edit_spec([op])
    assert parse_edit_spec([{"op": "recolor", "id": 12001, "color": "Dark_Blue"}]).ops[0].color == "Dark_Blue"


def test_recolor_color_takes_the_bank_code_of_the_nearest_colour_of_the_objects_class(tiny_synth):
    from sdn3d.data import vkitti1
    from sdn3d.data.scene_gt import scene_from_frame
    from sdn3d.editing.apply import EditError, SetBackgroundCode, SetCode
    from sdn3d.editing.spec import parse_edit_spec, resolve_ops
    from sdn3d.textural.codes import CodeBank

    scene = scene_from_frame(vkitti1.read_frames(tiny_synth)[4], (160, 64))
    car = int(scene.objects.instance_id[0])
    cls = car // 1000
    codes = {cls: torch.arange(15.0).view(3, 5), 3: torch.full((2, 5), 7.0)}
    colors = {cls: torch.tensor([[0.9, 0.9, 0.9], [0.7, 0.1, 0.1], [0.1, 0.2, 0.7]]),
              3: torch.tensor([[0.4] * 3, [0.1] * 3])}
    bank = CodeBank(codes, colors)
    spec = parse_edit_spec([{"op": "recolor", "id": car, "color": "red"}, {"op": "recolor", "id": car, "color": "blue"},
                            {"op": "recolor", "class": 3, "color": "black"}])
    from sdn3d.editing.appearance import appearance_renderer
    from sdn3d.textural.code_bank import named_color

    ops = resolve_ops(spec, scene, bank)
    assert ops[0] == SetCode(car, tuple(codes[cls][1].tolist()), named_color("red"))  # red, and its paint
    assert ops[1] == SetCode(car, tuple(codes[cls][2].tolist()), named_color("blue"))
    assert ops[2] == SetBackgroundCode(3, tuple(codes[3][1].tolist()))
    generator = appearance_renderer("generator")
    with pytest.raises(EditError, match=r"op 0 \(recolor id=\d+\): 'color: red' needs a code bank .*code_bank="):
        generator.check(spec, None)
    generator.check(spec, bank)
    appearance_renderer("photo").check(spec, None)
    with pytest.raises(EditError, match=r"needs a code bank with its objects' colours"):
        resolve_ops(spec, scene, CodeBank(codes))
    # Without a code bank a named colour keeps the object's code (the photo appearance repaints the car itself).
    photo = resolve_ops(parse_edit_spec([{"op": "recolor", "id": car, "color": "red"}]), scene, None)
    assert photo == [SetCode(car, tuple(scene.objects.code[0].tolist()), named_color("red"))]
    with pytest.raises(EditError, match=r"no training codes for class"):
        resolve_ops(spec, scene, CodeBank({3: codes[3]}, {3: colors[3]}))
