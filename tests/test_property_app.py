"""Property tests of sdn3d-app's HTTP interface (issue 42, "so that the next round finds less"): Hypothesis generates
requests to every route of the editor, malformed and hostile ones included (methods, paths with ``..``, encoded and
absolute paths, long and foreign ids, query strings, content types, Origin and Host headers, JSON bodies of edit
states valid and not, deep nesting, binary and oversize bodies, images), and checks that every answer is a result
(2xx, a PNG or JSON) or a clear refusal (a 4xx with a JSON ``{"error": ...}``), never a 500, never a hang (each
request has a time limit), and that no file outside a session's directory is removed or changed (a snapshot of a
directory beside the output directory, and of the session every request aims at).

Bounded: a derandomized, database-less profile and a few dozen requests per property (about 30 s on one core),
against one server with tiny random-weight checkpoints and the real Virtual KITTI frame at 248x75."""

from __future__ import annotations

import hashlib
import http.client
import io
import json
import time
import urllib.parse
from pathlib import Path

import numpy as np
import pytest
import test_property_specs as spec_props
from helpers.app_server import REAL_FRAME_ARGS, checkpoint_args, serving
from helpers.tiny_models import write_checkpoints
from hypothesis import example, given
from hypothesis import strategies as st
from PIL import Image

#: A request taking longer than this is a hang (the slowest honest one, a first de-render, takes a few seconds).
REQUEST_TIMEOUT_S = 60.0
BOXES = [[466, 203, 666, 333], [704, 194, 917, 305]]  # the real frame's two cars at 1242x375
SMALL = (248, 75)


def _png(array: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    Image.fromarray(array).save(buffer, format="PNG")
    return buffer.getvalue()


@pytest.fixture(scope="module")
def app(tmp_path_factory, real_vkitti_frame):
    """A server (small limits), its editor, a session of the real frame, and a canary directory beside the output."""
    root = tmp_path_factory.mktemp("app_props")
    ckpts = write_checkpoints(root / "ckpt")
    canary = root / "canary"
    canary.mkdir()
    for name in ("passwd", "input.png", "spec.yaml", "edited.png"):
        (canary / name).write_text(f"canary {name}\n")
    out = root / "out"
    frame = _png(np.asarray(Image.open(real_vkitti_frame).convert("RGB").resize(SMALL)))
    with serving([*checkpoint_args(ckpts), *REAL_FRAME_ARGS, f"output_dir={out}", "max_upload_bytes=200000",
                  "max_upload_pixels=500000", "max_request_bytes=4096", "max_sessions=64"]) as (base, editor):
        state = {"base": base, "editor": editor, "out": out, "canary": canary, "frame": frame, "root": root}
        state["sid"] = _open_session(state)
        yield state


def _open_session(app) -> str:
    status, _, body = _send(app["base"], "POST", "/api/open", app["frame"], {"Content-Type": "image/png"})
    assert status == 201, body
    return json.loads(body)["sid"]


def _send(base: str, method: str, path: str, body: bytes | None, headers: dict) -> tuple[int, dict, bytes]:
    url = urllib.parse.urlsplit(base)
    connection = http.client.HTTPConnection(url.hostname, url.port, timeout=REQUEST_TIMEOUT_S)
    try:
        try:
            connection.request(method, path, body=body, headers=headers)
        except (BrokenPipeError, ConnectionResetError):
            pass  # refused (413) before the whole body was sent: the answer is still to read
        response = connection.getresponse()
        return response.status, {k.lower(): v for k, v in response.headers.items()}, response.read()
    finally:
        connection.close()


def _snapshot(directory: Path) -> dict[str, str]:
    return {str(p.relative_to(directory)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(directory.rglob("*")) if p.is_file()}


# -- strategies ---------------------------------------------------------------------------------------------------

SID = "<sid>"  # the live session's id, put in when the request is sent
JUNK_SIDS = ["", "..", "%2e%2e", "..%2F..%2Fetc", "A" * 22, "A" * 64, "A" * 65, "a" * 5000, "%00", "%2Fetc%2Fpasswd",
             "nosuchsession", "-" * 16, "%C3%A9" * 20, "sessions", ".", "*"]
NAMES = ["edited.png", "edit.json", "edited_scene.glb", "spec.yaml", "command.txt", "input.png", "..%2Finput.png",
         "..%2F..%2F..%2Fetc%2Fpasswd", "../spec.yaml", "%2Fetc%2Fpasswd", "x" * 300, "", "index.html"]
segments = st.one_of(st.sampled_from([SID, *JUNK_SIDS]), st.text(max_size=30).map(lambda s: urllib.parse.quote(s,
                                                                                                              safe="")))
paths = st.one_of(
    st.sampled_from(["/", "/api/info", "/api/open", "/api/open_frame", "/static/app.js", "/static/app.css",
                     "/static/index.html", "/static/../../etc/passwd", "/static/%2e%2e%2f%2e%2e%2fetc%2fpasswd",
                     "/etc/passwd", "//etc/passwd", "/api/s/", "/api/", "/api/s"]),
    st.tuples(segments, st.sampled_from(["", "/", "/edit", "/box_at", "/input.png", "/edited.png", "/labels.png",
                                         "/download/", "/download/x", "/../input.png", "/./edit"]))
    .map(lambda t: f"/api/s/{t[0]}{t[1]}"),
    st.tuples(segments, st.sampled_from(NAMES)).map(lambda t: f"/api/s/{t[0]}/download/{t[1]}"),
    st.lists(segments, min_size=1, max_size=4).map(lambda parts: "/" + "/".join(parts)))
queries = st.one_of(st.just(""), st.dictionaries(st.sampled_from(["fx", "fy", "cx", "cy", "frame", "sid", "x"]),
                                                 st.one_of(st.sampled_from(["100", "49.5", "nan", "inf", "-1", "0",
                                                                            "1e400", "", "abc", "1" * 400]),
                                                           st.text(max_size=10)), max_size=4)
                    .map(lambda q: "?" + urllib.parse.urlencode(q) if q else ""))
methods = st.sampled_from(["GET", "POST", "DELETE", "PUT", "PATCH", "OPTIONS", "HEAD"])
boxes = st.one_of(st.sampled_from(BOXES), st.tuples(*[st.integers(-50, 1300)] * 4).map(list), spec_props.boxes)
states = st.fixed_dictionaries({}, optional={
    "objects": st.one_of(st.lists(st.fixed_dictionaries({"box": boxes}, optional={"class": st.sampled_from(
        ["Car", "Van", "Truck", "car", "Road", "Bus", 3, "../x"])}), max_size=3), spec_props.values),
    "ops": st.one_of(st.lists(st.one_of(spec_props.valid_ops(), spec_props.junk_ops), max_size=3), spec_props.values),
    "extra": spec_props.values})
json_bodies = st.one_of(states, st.fixed_dictionaries({"u": spec_props.numbers, "v": spec_props.numbers}),
                        st.fixed_dictionaries({"frame": spec_props.numbers}), spec_props.values)
BINARY = [b"", b"{not json", b"\xff\xfe", b"[" * 900 + b"]" * 900, b"[" * 5000, b"{" * 3000,
          b"\x89PNG\r\n\x1a\n" + b"garbage" * 10, b"GIF89a" + b"\0" * 100, b"\xff\xd8\xff" + b"\0" * 50,
          b"x" * 300_000, b'{"ops": [' + b'{"op": "delete", "id": 12001},' * 200 + b"]}"]
bodies = st.one_of(st.none(), st.sampled_from(BINARY), st.binary(max_size=200), json_bodies.map(
    lambda v: json.dumps(spec_props._expand(v), allow_nan=True).encode() if not _too_deep(v) else b"[]"),
    st.sampled_from(["<frame>", "<tiny png>", "<odd png>"]))
content_types = st.sampled_from(["application/json", "image/png", "image/jpeg", "text/plain", "", "multipart/form-data",
                                 "application/x-www-form-urlencoded", "application/json; charset=utf-16"])
origins = st.sampled_from([None, "http://127.0.0.1", "http://evil.example", "null", "file://"])
hosts = st.sampled_from([None, None, None, "localhost", "evil.example", "127.0.0.1:1", ""])
sec_fetch = st.sampled_from([None, "same-origin", "cross-site", "none"])


def _too_deep(value) -> bool:
    """A value JSON cannot write (nested past Python's recursion limit): sent as raw bytes instead (BINARY)."""
    return "<nested 3000>" in json.dumps(value, default=str)


def _body(app, token):
    if token == "<frame>":
        return app["frame"]
    if token == "<tiny png>":
        return _png(np.zeros((2, 2, 3), np.uint8))
    if token == "<odd png>":
        return _png(np.full((64, 64, 3), 128, np.uint8))
    return token


# -- the property -------------------------------------------------------------------------------------------------


def _check_answer(method: str, path: str, status: int, headers: dict, body: bytes) -> None:
    where = f"{method} {path} -> {status}: {body[:300]!r}"
    assert status < 500, where
    if 300 <= status < 400:
        assert "location" in headers, where
        return
    if method == "HEAD":
        return
    if status >= 400:
        try:
            answer = json.loads(body)
        except ValueError:
            raise AssertionError(f"not a JSON error: {where}") from None
        assert isinstance(answer, dict) and isinstance(answer.get("error"), str) and answer["error"], where
        return
    kind = headers.get("content-type", "")
    if kind.startswith("application/json"):
        json.loads(body)
    elif kind.startswith("image/png"):
        assert body.startswith(b"\x89PNG\r\n\x1a\n"), where


@spec_props.bounded(80)
@given(methods, paths, queries, bodies, content_types, origins, hosts, sec_fetch)
@example("POST", f"/api/s/{SID}/edit", "", b"[" * 900 + b"]" * 900, "application/json", None, None, None)
@example("POST", f"/api/s/{SID}/edit", "", json.dumps({"objects": [{"box": [0, 0, 1e300, 5]}]}).encode(),
         "application/json", None, None, None)
@example("POST", f"/api/s/{SID}/edit", "", json.dumps({"ops": [{"op": "zoom", "id": 12001, "zoom": 10**400}]}).encode(),
         "application/json", None, None, None)
@example("POST", f"/api/s/{SID}/box_at", "", b'{"u": 1e400, "v": 5}', "application/json", None, None, None)
@example("GET", "/api/info", "", None, "", None, "evil.example", None)
@example("POST", f"/api/s/{SID}/edit", "", b'{"ops": [{"op": "delete", "at": ' + b"[" * 900 + b"]" * 900 + b"}]}",
         "application/json", None, None, None)  # deep inside an op: the state's cleaner recurses
@example("POST", f"/api/s/{SID}/edit", "", json.dumps({"objects": [{"box": b} for b in BOXES], "ops": [
    {"op": "rotate", "id": 12001, "ry_deg": 30}, {"op": "recolor", "id": 12002, "color": "red"}]}).encode(),
         "application/json", None, None, None)
@example("DELETE", f"/api/s/{SID}", "", None, "", "http://evil.example", None, "cross-site")
def test_every_request_gets_a_result_or_a_json_4xx(app, method, path, query, body, content_type, origin, host,
                                                     fetch_site):
    sid = app["sid"]
    live = app["out"] / "sessions" / sid
    before_live, before_canary = _snapshot(live), _snapshot(app["canary"])
    headers = {"Content-Type": content_type} if content_type else {}
    for name, value in (("Origin", origin), ("Host", host), ("Sec-Fetch-Site", fetch_site)):
        if value is not None:
            headers[name] = value
    target = path.replace(SID, sid) + query
    started = time.monotonic()
    status, answer_headers, answer = _send(app["base"], method, target, _body(app, body), headers)
    assert time.monotonic() - started < REQUEST_TIMEOUT_S
    try:
        _check_answer(method, target, status, answer_headers, answer)
        # nothing outside a session's directory is touched; the live session loses nothing unless it was closed
        assert _snapshot(app["canary"]) == before_canary
        closed = method == "DELETE" and status == 200 and target.rstrip("/").endswith(sid)
        if not closed:
            after = _snapshot(live)
            lost = {k for k in before_live if k not in after and k != "spec.yaml"}
            assert not lost and after.get(next(k for k in before_live if k.startswith("input"))) == \
                before_live[next(k for k in before_live if k.startswith("input"))], (target, status, lost)
    finally:
        # sessions this request opened are closed again (max_sessions never evicts the live one); a closed live
        # session is opened again for the next example
        if status == 201:
            opened = json.loads(answer)["sid"]
            if opened != sid:
                _send(app["base"], "DELETE", f"/api/s/{opened}", None, {})
        if not app["editor"].sessions_dir.joinpath(sid).is_dir():
            app["sid"] = _open_session(app)
