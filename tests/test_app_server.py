"""sdn3d-app's HTTP interface and its safety (issue 30): it listens on 127.0.0.1 unless told, uploads are limited in
bytes and pixels (decompression bombs refused as sdn3d-edit refuses them), only PNG and JPEG are taken, no request
reaches the file system outside its session's directory, sessions never see each other's images, malformed requests
get a 4xx with a JSON error while the server goes on serving, nothing is written outside the output directory and
outputs are written atomically. Tiny random-weight checkpoints; the real Virtual KITTI frame (tests/data)."""

from __future__ import annotations

import errno
import io
import json
from pathlib import Path

import numpy as np
import pytest
from faults.images import declared_size_png
from helpers.app_server import REAL_FRAME_ARGS, checkpoint_args, json_request, request, serving
from helpers.tiny_models import write_checkpoints
from PIL import Image

from sdn3d.cli._config import compose_config
from sdn3d.cli.app import bind, edit_overrides, main
from sdn3d.data.imageio import MAX_IMAGE_PIXELS

BOXES = [{"box": [466, 203, 666, 333], "class": "Car"}, {"box": [704, 194, 917, 305], "class": "Car"}]


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


@pytest.fixture(scope="module")
def server(ckpts, tmp_path_factory):
    """``(base URL, Editor, output_dir)`` of a server with small limits (900 kB and 0.5 MP uploads, 4 kB requests;
    room for every session the tests open)."""
    out = tmp_path_factory.mktemp("app") / "out"
    with serving([*checkpoint_args(ckpts), *REAL_FRAME_ARGS, f"output_dir={out}", "max_upload_bytes=900000",
                  "max_upload_pixels=500000", "max_request_bytes=4096", "max_sessions=64"]) as (base, editor):
        yield base, editor, out


def _png(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(array).save(buffer, format="PNG")
    return buffer.getvalue()


def _small_frame(real_vkitti_frame: Path, size=(248, 75)) -> bytes:
    """The real frame at a smaller size of the same aspect ratio (the Virtual KITTI camera applies)."""
    return _png(np.asarray(Image.open(real_vkitti_frame).convert("RGB").resize(size)))


def _open(base, data: bytes, query: str = ""):
    return json_request(base, "POST", "/api/open" + query, data, content_type="image/png")


def _error(status, answer, expected_status, *needles):
    assert status == expected_status, (status, answer)
    assert set(answer) == {"error"}, answer
    for needle in needles:
        assert needle in answer["error"], answer


def test_the_server_listens_on_127_0_0_1_unless_told(ckpts, tmp_path):
    cfg = compose_config([], "app")
    assert cfg.host == "127.0.0.1"
    sock = bind(cfg.host, 0)
    try:
        assert sock.getsockname()[0] == "127.0.0.1"
    finally:
        sock.close()
    with serving([*checkpoint_args(ckpts), f"output_dir={tmp_path / 'out'}"]) as (base, _):
        assert request(base, "GET", "/api/info")[0] == 200
        # a page elsewhere reaching this server through a name of its own (DNS rebinding) is not answered
        assert request(base, "GET", "/api/info", headers={"Host": "attacker.example"})[0] == 400
    assert main([*checkpoint_args(ckpts), "host=", f"output_dir={tmp_path / 'b'}"]) == 2
    assert main([*checkpoint_args(ckpts), "port=70000", f"output_dir={tmp_path / 'b'}"]) == 2
    assert main([*checkpoint_args(ckpts), "input.image=x.png", f"output_dir={tmp_path / 'b'}"]) == 2


def test_the_command_line_repeats_the_edit_settings_only():
    argv = ["run=outputs/demo", "port=9", "host=0.0.0.0", "photo.fill=telea", "output_dir=/x", "threads=2",
            "max_sessions=3", "data=synth", "data.root=/d"]
    assert edit_overrides(argv) == ["run=outputs/demo", "photo.fill=telea", "threads=2", "data=synth", "data.root=/d"]


def test_uploads_are_limited_in_bytes_and_pixels(server, real_vkitti_frame, tmp_path):
    base, _, _ = server
    _error(*_open(base, b"\x89PNG\r\n\x1a\n" + b"\0" * 1_000_000), 413, "more than the 900000")
    # a few hundred bytes declaring 30 MP: refused from the header, before decoding (max_upload_pixels)
    bomb = declared_size_png(tmp_path / "bomb.png", 6000, 5000).read_bytes()
    assert len(bomb) < 1000
    _error(*_open(base, bomb), 413, "6000x5000", "max_upload_pixels")
    # beyond the project's reader limit (100 MP): sdn3d-edit's own refusal
    huge = declared_size_png(tmp_path / "huge.png", 20000, 20000).read_bytes()
    assert 20000 * 20000 > MAX_IMAGE_PIXELS
    _error(*_open(base, huge), 422, "too large", "decompression bomb")
    # issue 42 (5): an aspect ratio far from the working size's is refused from its header too (it was scaled to
    # cover the working size before the crop: a 10x20000 PNG took 18.5 GB)
    tall = declared_size_png(tmp_path / "tall.png", 10, 20000).read_bytes()
    _error(*_open(base, tall, "?fx=725&fy=725&cx=5&cy=10000"), 422, "10x20000", "too far from the working size")
    status, answer = _open(base, _small_frame(real_vkitti_frame))
    assert status == 201, answer


def test_only_png_and_jpeg_are_accepted(server, real_vkitti_frame):
    base, _, _ = server
    for data in (b"GIF89a" + b"\0" * 100, b"<html><script>alert(1)</script></html>", b"%PDF-1.4", b"BM" + b"\0" * 64):
        _error(*_open(base, data), 415, "only PNG and JPEG")
    _error(*_open(base, b"\x89PNG\r\n\x1a\n" + b"garbage" * 10), 422)  # PNG's signature, no PNG
    jpeg = io.BytesIO()
    Image.open(real_vkitti_frame).convert("RGB").resize((248, 75)).save(jpeg, format="JPEG")
    assert _open(base, jpeg.getvalue())[0] == 201
    # the camera rules of sdn3d-edit: another aspect ratio needs intrinsics, and then is accepted
    odd = _png(np.zeros((100, 100, 3), np.uint8))
    # in the page's own words (issue 42): its camera fields, not sdn3d-edit's input.intrinsics=...
    status, answer = _open(base, odd)
    _error(status, answer, 422, "camera is unknown", "open 'camera' in the toolbar", "pixels of this 100x100 image")
    assert "input.intrinsics" not in answer["error"] and "input.camera" not in answer["error"]
    assert _open(base, odd, "?fx=100&fy=100&cx=49.5&cy=49.5")[0] == 201


def test_no_request_reaches_the_file_system(server, real_vkitti_frame):
    base, editor, out = server
    status, view = _open(base, _small_frame(real_vkitti_frame))
    sid = view["sid"]
    for path in ("/static/../../../../etc/passwd", "/static/%2e%2e%2f%2e%2e%2fetc%2fpasswd", "/static/editor.py",
                 f"/api/s/{sid}/download/..%2finput.png", f"/api/s/{sid}/download/..%2F..%2F..%2Fetc%2Fpasswd",
                 f"/api/s/{sid}/download/input.png", "/api/s/..%2F..%2Fetc/input.png",
                 "/api/s/" + "A" * 22 + "/input.png", "/etc/passwd"):
        status, _, body = request(base, "GET", path)
        assert status == 404 and b"root:" not in body, path
        assert "error" in json.loads(body), path
    # what the browser sends is never a path: a colour name like one is refused by the spec's parser
    status, answer = json_request(base, "POST", f"/api/s/{sid}/edit",
                                  {"objects": BOXES[:1], "ops": [{"op": "recolor", "id": 12001,
                                                                  "color": "../../etc/passwd"}]})
    _error(status, answer, 422, "unknown colour")
    assert not any(p.name == "passwd" for p in out.rglob("*"))


def test_two_sessions_never_see_each_others_images(server, real_vkitti_frame):
    base, editor, _ = server
    first = _small_frame(real_vkitti_frame)
    second = _png(255 - np.asarray(Image.open(io.BytesIO(first))))
    a, b = _open(base, first)[1]["sid"], _open(base, second)[1]["sid"]
    assert a != b and len(a) >= 22
    pictures = {sid: np.asarray(Image.open(io.BytesIO(request(base, "GET", f"/api/s/{sid}/input.png")[2])))
                for sid in (a, b)}
    assert np.array_equal(pictures[a], np.asarray(Image.open(io.BytesIO(first))))
    assert np.array_equal(pictures[b], np.asarray(Image.open(io.BytesIO(second))))
    assert editor.get(a).directory != editor.get(b).directory
    assert request(base, "DELETE", f"/api/s/{a}")[0] == 200
    assert request(base, "GET", f"/api/s/{a}/input.png")[0] == 404 and not editor.sessions_dir.joinpath(a).exists()
    assert request(base, "GET", f"/api/s/{b}/input.png")[0] == 200


def test_malformed_requests_get_a_json_4xx_and_the_server_goes_on(server, real_vkitti_frame):
    base, _, _ = server
    sid = _open(base, real_vkitti_frame.read_bytes())[1]["sid"]
    edit = f"/api/s/{sid}/edit"
    bad = [("POST", edit, b"{not json", 400), ("POST", edit, b"\xff\xfe", 400), ("POST", edit, b"[" * 5000, 413),
           ("POST", edit, b"[" * 2000 + b"]" * 2000, 400),
           ("POST", edit, [1, 2], 422), ("POST", edit, {"ops": "delete everything"}, 422),
           ("POST", edit, {"ops": [{"op": "move", "id": 12001, "to": [1e400, 0]}]}, 422),
           ("POST", edit, {"ops": [{"op": "explode", "id": 12001}]}, 422),
           ("POST", edit, {"ops": [{"op": "move", "id": 12001, "to": "here"}]}, 422),
           ("POST", edit, {"ops": [{"op": "rotate", "id": 12001, "ry_deg": 45}]}, 422),  # no box: no object
           ("POST", edit, {"objects": [{"box": [1, 2], "class": "Car"}], "ops": []}, 422),
           ("POST", edit, {"ops": [{"op": "delete", "id": 2**70}]}, 422),
           ("POST", edit, {"extra": 1}, 422), ("POST", "/api/open_frame", {"frame": 0}, 400),
           ("POST", "/api/open_frame", {"frame": "../x"}, 400), ("POST", "/api/open", b"", 400),
           ("POST", "/api/open?fx=abc", b"\x89PNG\r\n\x1a\n", 400), ("GET", "/api/nothing", None, 404),
           ("PUT", "/api/info", b"", 405), ("GET", f"/api/s/{sid}/labels.png", None, 409)]
    for method, path, body, expected in bad:
        status, _, data = request(base, method, path, body)
        assert status == expected, (method, path, body, status, data[:200])
        assert "error" in json.loads(data)
    assert request(base, "GET", "/api/info")[0] == 200
    status, view = json_request(base, "POST", edit, {"objects": BOXES, "ops": [{"op": "delete", "id": 12002}]})
    assert status == 200 and [o["id"] for o in view["objects"]] == [12001]


def test_nothing_is_written_outside_the_output_directory(ckpts, real_vkitti_frame, tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    monkeypatch.chdir(work)
    out = tmp_path / "out"
    before = {p for p in tmp_path.rglob("*")}
    with serving([*checkpoint_args(ckpts), *REAL_FRAME_ARGS, f"output_dir={out}"]) as (base, _):
        sid = _open(base, real_vkitti_frame.read_bytes())[1]["sid"]
        ops = [{"op": "rotate", "id": 12001, "ry_deg": 30}, {"op": "delete", "id": 12002}]
        assert json_request(base, "POST", f"/api/s/{sid}/edit", {"objects": BOXES, "ops": ops})[0] == 200
        for name in ("edited.png", "edit.json", "edited_scene.glb", "spec.yaml", "command.txt"):
            assert request(base, "GET", f"/api/s/{sid}/download/{name}")[0] == 200
    new = {p for p in tmp_path.rglob("*")} - before
    assert new and all(p == out or out in p.parents for p in new), sorted(map(str, new - {out}))
    assert not list(work.iterdir())


def test_downloads_are_written_atomically(server, real_vkitti_frame, monkeypatch):
    """A download whose writing fails leaves the previous file whole and no partial file behind."""
    import PIL.Image

    base, editor, _ = server
    sid = _open(base, _small_frame(real_vkitti_frame))[1]["sid"]
    assert request(base, "GET", f"/api/s/{sid}/download/edited.png")[0] == 200
    path = editor.get(sid).directory / "edited.png"
    first = path.read_bytes()
    small_box = [{"box": [93, 40, 133, 67], "class": "Car"}]  # the near car, in the 248x75 frame's pixels
    status, view = json_request(base, "POST", f"/api/s/{sid}/edit",
                                {"objects": small_box, "ops": [{"op": "delete", "id": 12001}]})
    assert status == 200, view

    def fail(self, handle, *args, **kwargs):
        handle.write(b"\x89PNG partial")
        raise OSError("disk full")

    monkeypatch.setattr(PIL.Image.Image, "save", fail)
    status, _, body = request(base, "GET", f"/api/s/{sid}/download/edited.png")
    assert status == 500 and "internal error" in json.loads(body)["error"]
    assert path.read_bytes() == first
    assert not [p for p in path.parent.iterdir() if p.name.endswith(".tmp")]
    # issue 42 (8): a full disk is said so (507, naming the file), not "internal error" (500)

    def full(self, handle, *args, **kwargs):
        handle.write(b"\x89PNG partial")
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(PIL.Image.Image, "save", full)
    status, _, body = request(base, "GET", f"/api/s/{sid}/download/edited.png")
    assert status == 507, body
    assert json.loads(body)["error"].startswith(f"the disk is full: could not write {str(path)!r} (No space left on "
                                                "device); nothing half-written is left"), body
    assert path.read_bytes() == first
    assert not [p for p in path.parent.iterdir() if p.name.endswith(".tmp")]
    monkeypatch.undo()
    assert request(base, "GET", "/api/info")[0] == 200  # still serving


def test_sessions_beyond_the_limit_close_only_an_idle_one(ckpts, real_vkitti_frame, tmp_path, monkeypatch):
    """Issue 42 (1): opening more images than max_sessions never closes a session in use: the new one is refused
    (503, before any de-render) until the least recently used has been idle for session_idle_s."""
    with serving([*checkpoint_args(ckpts), *REAL_FRAME_ARGS, f"output_dir={tmp_path / 'out'}",
                  "max_sessions=2", "session_idle_s=60"]) as (base, editor):
        data = _small_frame(real_vkitti_frame)
        sids = [_open(base, data)[1]["sid"] for _ in range(2)]
        calls = []
        monkeypatch.setattr(editor.session, "derender", lambda *a, **k: calls.append(a) or 1 / 0)
        for _ in range(8):
            _error(*_open(base, data), 503, "max_sessions", "session_idle_s=60")
        assert not calls  # no de-render spent on a refused open
        assert all(request(base, "GET", f"/api/s/{s}/input.png")[0] == 200 for s in sids)
        assert sorted(p.name for p in editor.sessions_dir.iterdir()) == sorted(sids)
        monkeypatch.undo()
        # 61 s later the least recently used (sids[0]: sids[1] was asked for last) is idle: it makes room
        for found in editor._sessions.values():
            found.used -= 61
        status, answer = _open(base, data)
        assert status == 201, answer
        assert request(base, "GET", f"/api/s/{sids[0]}/input.png")[0] == 404
        assert sorted(p.name for p in editor.sessions_dir.iterdir()) == sorted([sids[1], answer["sid"]])


def test_another_website_cannot_open_edit_or_close_a_session(server, real_vkitti_frame):
    """Issue 42 (1): a write from another origin (Origin, Sec-Fetch-Site) is refused with 403, and a body a browser
    sends across sites without a preflight (text/plain, a form) with 415, before it is read: no session is opened,
    edited or closed. The page's own requests (same Origin, JSON, an image type) go through."""
    base, editor, _ = server
    data = _small_frame(real_vkitti_frame)
    status, view = _open(base, data)
    assert status == 201, view
    sid = view["sid"]
    before = sorted(editor._sessions)
    evil = {"Origin": "http://evil.example"}
    _error(*json_request(base, "POST", "/api/open", data, content_type="text/plain"), 415, "text/plain")
    _error(*json_request(base, "POST", "/api/open", data, content_type="image/png", headers=evil), 403,
           "another origin")
    _error(*json_request(base, "POST", "/api/open", data, content_type="image/png",
                         headers={"Sec-Fetch-Site": "cross-site"}), 403, "another site")
    _error(*json_request(base, "POST", "/api/open", data, content_type="image/png", headers={"Origin": "null"}),
           403, "another origin")
    for form in ("application/x-www-form-urlencoded", "multipart/form-data; boundary=x"):
        _error(*json_request(base, "POST", "/api/open_frame", b'{"frame": 0}', content_type=form), 415)
    _error(*json_request(base, "POST", f"/api/s/{sid}/edit", b'{"ops": []}', content_type="text/plain"), 415)
    _error(*json_request(base, "POST", f"/api/s/{sid}/edit", {"ops": []}, headers=evil), 403)
    _error(*json_request(base, "DELETE", f"/api/s/{sid}", headers=evil), 403)
    _error(*json_request(base, "DELETE", f"/api/s/{sid}", headers={"Sec-Fetch-Site": "same-site"}), 403)
    # a JSON endpoint takes application/json only
    _error(*json_request(base, "POST", f"/api/s/{sid}/edit", b'{"ops": []}', content_type="image/png"), 415,
           "application/json")
    assert sorted(editor._sessions) == before
    # the page's own requests: its Origin, Sec-Fetch-Site same-origin
    page = {"Origin": base, "Sec-Fetch-Site": "same-origin"}
    status, answer = json_request(base, "POST", f"/api/s/{sid}/edit", {"ops": []}, headers=page)
    assert status == 200, answer
    status, answer = json_request(base, "POST", "/api/open", data, content_type="image/png", headers=page)
    assert status == 201, answer
    assert json_request(base, "DELETE", f"/api/s/{answer['sid']}", headers=page)[0] == 200


def test_a_click_on_a_car_implies_its_box_which_the_page_adds(server, real_vkitti_frame):
    """POST box_at: a click on the red car of the real frame gives its box (as a person would draw it), which then
    edits like a drawn box; a malformed or outside point gets a JSON 4xx and changes nothing."""
    base, _, _ = server
    sid = _open(base, real_vkitti_frame.read_bytes())[1]["sid"]
    status, answer = json_request(base, "POST", f"/api/s/{sid}/box_at", {"u": 600, "v": 280})
    assert status == 200 and set(answer) == {"box", "refused"} and answer["refused"] is None
    box, drawn = answer["box"], BOXES[0]["box"]
    inter = (max(0, min(box[2], drawn[2]) - max(box[0], drawn[0]))
             * max(0, min(box[3], drawn[3]) - max(box[1], drawn[1])))
    union = (box[2] - box[0]) * (box[3] - box[1]) + (drawn[2] - drawn[0]) * (drawn[3] - drawn[1]) - inter
    assert inter / union > 0.8, box
    for body, expected in (({"u": 1}, 400), ({"u": "a", "v": 2}, 400), ({"u": True, "v": 2}, 400),
                           ({"u": 5000, "v": 10}, 422), ({"u": -1, "v": 10}, 422), ([600, 280], 400)):
        _error(*json_request(base, "POST", f"/api/s/{sid}/box_at", body), expected)
    _error(*json_request(base, "POST", "/api/s/nosuchsession/box_at", {"u": 1, "v": 1}), 404)
    status, view = json_request(base, "POST", f"/api/s/{sid}/edit", {"objects": [{"box": box, "class": "Car"}],
                                                                       "ops": []})
    assert status == 200 and [o["id"] for o in view["objects"]] == [12001]


def test_a_click_or_box_where_no_vehicle_is_is_refused_unless_forced(server, real_vkitti_frame):
    """Issue 42: Alt+click on empty road (it implied an 888x175 'Car') or on the sky (a 7x6 px one), and a box whose
    fit finds no car, are refused with the reason; nothing is added; force: true adds it all the same."""
    base, _, _ = server
    sid = _open(base, real_vkitti_frame.read_bytes())[1]["sid"]
    for u, v, why in ((300, 340, "GrabCut found no object under the click"),
                      (600, 50, "its bottom edge (row 54) is above the horizon (row 187)")):
        status, answer = json_request(base, "POST", f"/api/s/{sid}/box_at", {"u": u, "v": v})
        assert status == 200 and answer["refused"].startswith(f"no vehicle at ({u}, {v}): ") and why in \
            answer["refused"], answer
    sky = [590, 40, 640, 60]  # a box in the sky: its bottom is above the horizon
    status, answer = json_request(base, "POST", f"/api/s/{sid}/edit", {"objects": [{"box": sky, "class": "Car"}],
                                                                         "ops": []})
    assert status == 422 and answer["refused_objects"] == [0], answer
    assert "objects[0] (box [590.0, 40.0, 640.0, 60.0], Car): no vehicle there: its bottom edge (row 60) is above " \
           "the horizon" in answer["error"] and "give it force: true" in answer["error"]
    status, view = json_request(base, "GET", f"/api/s/{sid}")
    assert view["objects"] == [] and view["state"] == {"objects": [], "ops": []}  # nothing added
    status, view = json_request(base, "POST", f"/api/s/{sid}/edit",
                                {"objects": [{"box": sky, "class": "Car", "force": True}], "ops": []})
    assert status == 200 and [o["id"] for o in view["objects"]] == [12001] and "force: true" in view["spec"]


def test_the_page_names_an_upload_by_its_own_name_and_says_where_the_labels_come_from(server, real_vkitti_frame):
    """Issue 42: the uploaded file's own name (shown only: the upload is stored as input.png); a labels overlay from
    a semantic branch of unknown quality (these tests' random weights: no summary.json) says so."""
    base, _, _ = server
    status, view = _open(base, real_vkitti_frame.read_bytes(), "?name=" + "..%2Fmy%20street%0A.png")
    assert status == 201 and view["input"]["name"] == "my street.png" and view["input"]["file"] == "input.png"
    assert view["labels_note"].startswith("labels: from a semantic branch whose validation quality is not recorded")
    assert _open(base, real_vkitti_frame.read_bytes())[1]["input"]["name"] == "input.png"  # no name given


def test_an_empty_state_lists_no_objects_of_the_state_before(server, real_vkitti_frame):
    """Reset (the empty state) after edits: with proposals=boxes nothing is listed any more, not the last scene."""
    base, _, _ = server
    sid = _open(base, real_vkitti_frame.read_bytes())[1]["sid"]
    status, view = json_request(base, "POST", f"/api/s/{sid}/edit", {"objects": BOXES,
                                                                       "ops": [{"op": "delete", "id": 12002}]})
    assert status == 200 and [o["id"] for o in view["objects"]] == [12001]
    status, view = json_request(base, "POST", f"/api/s/{sid}/edit", {"objects": [], "ops": []})
    assert status == 200 and view["objects"] == [] and view["state"] == {"objects": [], "ops": []}


def test_a_deeply_nested_request_gets_a_4xx_not_a_500(server, real_vkitti_frame):
    """Issue 42 (9): a list nested 900 deep in /edit ran into RecursionError (500); now 422 naming the field, and the
    server goes on."""
    base, _, _ = server
    status, view = _open(base, _small_frame(real_vkitti_frame))
    assert status == 201, view
    body = ('{"ops": [{"op": "move", "to": ' + "[" * 900 + "1" + "]" * 900 + "}]}").encode()
    _error(*json_request(base, "POST", f"/api/s/{view['sid']}/edit", body), 422, "ops[0].to[0][0]")
    assert request(base, "GET", "/api/info")[0] == 200


@pytest.mark.parametrize("stop", ["SIGINT", "SIGTERM"])
def test_ctrl_c_stops_cleanly_and_says_what_is_kept(ckpts, real_vkitti_frame, tmp_path, stop):
    """Issue 42 (editor 3): Ctrl+C (or SIGTERM) printed a 30-line KeyboardInterrupt traceback and exited 130; now exit
    0 and one line saying where the sessions' files are kept and until when. The next start removes the session
    directories the app wrote and keeps one holding a file it did not write (named)."""
    import os
    import signal
    import subprocess
    import sys

    out = tmp_path / "out"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    args = [sys.executable, "-m", "sdn3d.cli.app", *checkpoint_args(ckpts), *REAL_FRAME_ARGS, f"output_dir={out}",
            "port=0"]
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        line = proc.stdout.readline()
        assert "serving http://127.0.0.1:" in line, (line, proc.stderr.read() if proc.poll() is not None else "")
        base = line.split("serving ", 1)[1].split("/ ", 1)[0]
        status, view = _open(base, _small_frame(real_vkitti_frame))
        assert status == 201, view
        proc.send_signal(getattr(signal, stop))
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 0, err
    assert "Traceback" not in err and "KeyboardInterrupt" not in err, err
    assert (f"sdn3d-app: stopped; the files of 1 session(s) (uploads, spec.yaml, downloads: what the page's command "
            f"lines read) are kept in {out / 'sessions'} until the next sdn3d-app with output_dir={out} starts, which "
            "removes them") in err, err
    mine = out / "sessions" / ("m" * 22)
    (mine / "sdn3d-edit").mkdir(parents=True)  # the output of a session's sdn3d-edit command line: not the app's
    if stop == "SIGTERM":
        return
    proc = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    try:
        assert "serving http://127.0.0.1:" in proc.stdout.readline()
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert f"sdn3d-app: removed 1 session directory of an earlier run from {out / 'sessions'}" in err, err
    assert f"sdn3d-app: kept 1 entry of an earlier run holding files it did not write: {mine}" in err, err
    assert [p.name for p in (out / "sessions").iterdir()] == [mine.name]


def test_a_large_upload_is_scaled_down_for_editing(server, real_vkitti_frame, monkeypatch):
    """Issue 42 (6): the editor accepted a 25 MP upload, and one click then took 80 s (a box plus a turn grew past
    6.6 GB): the work grows with the input's pixels. Now an upload over max_edit_pixels is scaled down to it when
    opened (its camera following), that copy is the session's input, and the page says so."""
    import dataclasses

    base, editor, _ = server
    monkeypatch.setattr(editor, "limits", dataclasses.replace(editor.limits, max_edit_pixels=20000))
    status, view = _open(base, _small_frame(real_vkitti_frame, (496, 150)))
    assert status == 201, view
    assert (view["input"]["width"], view["input"]["height"]) == (257, 77), view["input"]
    assert view["warnings"][0].startswith("the 496x150 upload was scaled to 257x77 for editing (max_edit_pixels=20000")
    directory = editor.get(view["sid"]).directory
    assert sorted(p.name for p in directory.iterdir()) == ["input.png", "spec.yaml"]
    assert f"input.image={directory / 'input.png'}" in view["command"]
    # a camera given in the upload's pixels follows the resize (Intrinsics.resized)
    photo = _png(np.full((300, 400, 3), 90, np.uint8))
    status, view = _open(base, photo, "?fx=400&fy=400&cx=199.5&cy=149.5")
    assert status == 201, view
    assert (view["input"]["width"], view["input"]["height"]) == (163, 122)
    camera = view["camera"]
    assert camera["fx"] == pytest.approx(400 * 163 / 400) and camera["fy"] == pytest.approx(400 * 122 / 300)
    assert camera["cx"] == pytest.approx(200 * 163 / 400 - 0.5) and camera["cy"] == pytest.approx(150 * 122 / 300 - 0.5)
