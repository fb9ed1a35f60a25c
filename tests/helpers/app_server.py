"""``sdn3d-app`` in a thread for the tests: :func:`serving` builds it from ``conf/app.yaml`` overrides (tiny
checkpoints), listens on a free port of 127.0.0.1 and stops it afterwards; :func:`request` is a small HTTP client
(the standard library's) that returns every answer, 4xx and 5xx included."""

from __future__ import annotations

import http.client
import json
import threading
import time
import urllib.parse
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from typing import Any

REAL_FRAME_ARGS = ("proposals=boxes", "image_size=[312,96]", "geometric.crop_size=32")
"""Settings of a server for the real Virtual KITTI frame (objects from drawn boxes, a small working size)."""


def checkpoint_args(ckpts: dict) -> list[str]:
    return [f"checkpoints.{k}={v}" for k, v in ckpts.items()]


@contextmanager
def serving(overrides: Sequence[str]) -> Iterator[tuple[str, Any]]:
    """``(base URL, Editor)`` of an ``sdn3d-app`` built from ``overrides`` and served on a free port until the block
    ends."""
    import uvicorn

    from sdn3d.cli._config import compose_config
    from sdn3d.cli.app import bind, build_app

    cfg = compose_config([*overrides, "port=0"], "app")
    app, editor = build_app(cfg, list(overrides))
    sock = bind(str(cfg.host), 0)
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", access_log=False, lifespan="off"))
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    deadline = time.monotonic() + 20
    while not server.started:
        if time.monotonic() > deadline or not thread.is_alive():
            raise RuntimeError("sdn3d-app did not start")
        time.sleep(0.02)
    try:
        yield f"http://127.0.0.1:{sock.getsockname()[1]}", editor
    finally:
        server.should_exit = True
        thread.join(20)
        sock.close()


def request(base: str, method: str, path: str, body: Any = None, content_type: str = "application/json",
            headers: dict | None = None) -> tuple[int, dict[str, str], bytes]:
    """``(status, headers, body)`` of one request; ``body``: bytes as they are, anything else as JSON."""
    data = body if body is None or isinstance(body, bytes) else json.dumps(body).encode()
    url = urllib.parse.urlsplit(base)
    connection = http.client.HTTPConnection(url.hostname, url.port, timeout=120)
    try:
        try:
            connection.request(method, url.path + path, body=data,
                               headers={"Content-Type": content_type, **(headers or {})})
        except (BrokenPipeError, ConnectionResetError):
            pass  # the server answered (413) and closed before the whole body was sent: its answer is still to read
        response = connection.getresponse()
        return response.status, dict(response.headers), response.read()
    finally:
        connection.close()


def json_request(base: str, method: str, path: str, body: Any = None, **kwargs: Any) -> tuple[int, Any]:
    """``(status, JSON answer)`` of :func:`request`."""
    status, _, data = request(base, method, path, body, **kwargs)
    return status, json.loads(data)
