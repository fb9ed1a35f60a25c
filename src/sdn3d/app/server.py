"""The editor's HTTP interface (Starlette) and its page.

Every answer is JSON (errors: ``{"error": "<what and why>"}`` with a 4xx status; a bug: 500 and the traceback in the
server's log, and the server goes on serving) or an image (PNG) or a download. Routes (``<sid>``: a browser
session's id, :mod:`sdn3d.app.editor`)::

    GET    /                                 the page (static/index.html); /static/app.js, /static/app.css
    GET    /api/info                         frames to pick, colour palette, limits, settings
    POST   /api/open[?fx=&fy=&cx=&cy=]       body: a PNG or JPEG file -> a new session (de-rendered), its view
    POST   /api/open_frame                   {"frame": index} -> a new session of a dataset frame, its view
    GET    /api/s/<sid>                      the session's view (objects, spec, command, warnings)
    POST   /api/s/<sid>/edit                 {"objects": [...], "ops": [...]} -> the new state's view
    POST   /api/s/<sid>/box_at               {"u": x, "v": y} -> {"box": [x0, y0, x1, y1]}: the box a click implies
    GET    /api/s/<sid>/input.png            the input at its resolution
    GET    /api/s/<sid>/edited.png           the current picture at the input's resolution
    GET    /api/s/<sid>/labels.png           the current scene's semantic map (working size, class colours)
    GET    /api/s/<sid>/download/<name>      edited.png, edit.json, edited_scene.glb, spec.yaml, command.txt
    DELETE /api/s/<sid>                      close the session (its directory removed)

Request bodies are read up to a limit (``max_upload_bytes`` for images, ``max_request_bytes`` for JSON) and
refused with 413 beyond it, before they are kept whole. Only ``Host`` names of the address the server listens on
are answered (a web page elsewhere cannot reach a local server through a name of its own: DNS rebinding).

Writes (POST, DELETE) come from the page only (:class:`SameOriginWrites`): one whose ``Origin`` is not the server's
own or whose ``Sec-Fetch-Site`` says another site sent it is refused (403), and a body of a type a browser sends
across sites without asking first (``text/plain``, a form) is refused (415): JSON requests are
``application/json``, uploads an image type. Another website cannot open, edit or close a session.
"""

from __future__ import annotations

import json
import logging
from importlib import resources
from typing import Any

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException
from starlette.middleware import Middleware
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Route

from sdn3d.app.editor import DOWNLOADS, AppError, Editor, palette
from sdn3d.errors import UserInputError
from sdn3d.io import is_disk_full

__all__ = ["create_app", "STATIC_FILES", "allowed_hosts", "SameOriginWrites", "SIMPLE_TYPES"]

#: The page's files, served by name from the package (no path from a request reaches the file system).
STATIC_FILES = {"index.html": "text/html; charset=utf-8", "app.js": "text/javascript; charset=utf-8",
                "app.css": "text/css; charset=utf-8"}
_NO_STORE = {"Cache-Control": "no-store", "X-Content-Type-Options": "nosniff"}
log = logging.getLogger("sdn3d.app")
#: Body types a browser sends to another site without a preflight (CORS "simple" requests): never accepted.
SIMPLE_TYPES = ("text/plain", "application/x-www-form-urlencoded", "multipart/form-data")
_READS = ("GET", "HEAD", "OPTIONS")


def allowed_hosts(host: str) -> list[str]:
    """The ``Host`` names answered for a server listening on ``host``: the loopback names for a loopback address,
    any name when it listens on every address (``0.0.0.0``, ``::``: asked for explicitly), else that address."""
    if host in ("0.0.0.0", "::"):
        return ["*"]
    loopback = ["127.0.0.1", "localhost", "[::1]", "::1"]
    return loopback if host in loopback else [host]


def _write_refusal(scope: dict) -> tuple[str, int] | None:
    """Why a request that writes (any method but GET, HEAD, OPTIONS) is refused, with its status, or None: it must
    come from the page itself (no ``Origin`` but the server's own, no ``Sec-Fetch-Site`` but ``same-origin`` or
    ``none``) and carry no body type a browser sends across sites without a preflight (:data:`SIMPLE_TYPES`)."""
    headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", ())}
    site = headers.get("sec-fetch-site")
    if site is not None and site.strip().lower() not in ("same-origin", "none"):
        return f"a write from another site (Sec-Fetch-Site: {site[:20]}) is refused: use the editor's own page", 403
    origin = headers.get("origin")
    if origin is not None:
        host = headers.get("host", "").strip().lower()
        parts = origin.strip().lower().split("://", 1)
        if len(parts) != 2 or parts[0] not in ("http", "https") or not host or parts[1].rstrip("/") != host:
            return f"a write from another origin ({origin[:60]}) is refused: use the editor's own page", 403
    media = headers.get("content-type", "").split(";", 1)[0].strip().lower()
    if media in SIMPLE_TYPES:
        return (f"a {media} body is refused (a browser sends it from any site without asking): send JSON as "
                "application/json, an image as image/png or image/jpeg"), 415
    return None


def host_name(host_header: str) -> str:
    """The name in a ``Host`` header, its port left out (``[::1]:8030`` -> ``[::1]``, ``localhost:8030`` ->
    ``localhost``)."""
    host = host_header.strip()
    if host.startswith("["):
        end = host.find("]")
        return host[:end + 1] if end > 0 else host
    return host.split(":", 1)[0]


class KnownHosts:
    """ASGI middleware: a request whose ``Host`` is not a name of the listening address (:func:`allowed_hosts`; a
    DNS-rebinding page's) is answered 400 with a JSON error naming the host, as every other refusal is."""

    def __init__(self, app: Any, hosts: list[str]) -> None:
        self.app = app
        self.hosts = {h.lower() for h in hosts}

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        if scope["type"] == "http" and "*" not in self.hosts:
            headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope.get("headers", ())}
            name = host_name(headers.get("host", "")).lower()
            if name not in self.hosts:
                shown = name[:80] or "(none)"
                await _json({"error": f"the Host {shown!r} is not a name of this server "
                                      f"({', '.join(sorted(self.hosts))}): open the editor at its own address"},
                            400)(scope, receive, send)
                return
        await self.app(scope, receive, send)


class SameOriginWrites:
    """ASGI middleware: a request that writes is answered 403 / 415 unless it comes from the page
    (:func:`_write_refusal`), before its body is read or a session is touched."""

    def __init__(self, app: Any) -> None:
        self.app = app

    async def __call__(self, scope: dict, receive: Any, send: Any) -> None:
        if scope["type"] == "http" and scope["method"] not in _READS:
            refused = _write_refusal(scope)
            if refused is not None:
                await _json({"error": refused[0]}, refused[1])(scope, receive, send)
                return
        await self.app(scope, receive, send)


def _json(payload: Any, status: int = 200) -> JSONResponse:
    return JSONResponse(payload, status, headers=_NO_STORE)


def _png(data: bytes, **headers: str) -> Response:
    return Response(data, media_type="image/png", headers={**_NO_STORE, **headers})


async def _body(request: Request, limit: int, what: str) -> bytes:
    """The request's body, refused (413) as soon as it is longer than ``limit`` bytes."""
    declared = request.headers.get("content-length")
    if declared is not None and (not declared.isdigit() or int(declared) > limit):
        raise AppError(f"the {what} is {declared} bytes, more than the {limit} accepted", 413)
    chunks, size = [], 0
    async for chunk in request.stream():
        size += len(chunk)
        if size > limit:
            raise AppError(f"the {what} is more than the {limit} bytes accepted", 413)
        chunks.append(chunk)
    return b"".join(chunks)


async def _json_body(request: Request, limit: int) -> Any:
    media = request.headers.get("content-type", "").split(";", 1)[0].strip().lower()
    if media != "application/json":
        raise AppError(f"send the request as application/json, not {media[:40] or 'no content type'}", 415)
    data = await _body(request, limit, "request")
    try:
        return json.loads(data.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError):
        raise AppError("the request body is not JSON", 400) from None


def create_app(editor: Editor, info: dict[str, Any], hosts: list[str] | None = None) -> Starlette:
    """The Starlette application serving ``editor`` (module doc); ``info``: extra fields of ``/api/info``;
    ``hosts``: the ``Host`` names answered (:func:`allowed_hosts`; None: the loopback names)."""
    static = {name: resources.files("sdn3d.app").joinpath("static", name).read_bytes() for name in STATIC_FILES}
    limits = editor.limits

    async def page(request: Request) -> Response:
        return Response(static["index.html"], media_type=STATIC_FILES["index.html"], headers=_NO_STORE)

    async def static_file(request: Request) -> Response:
        name = request.path_params["name"]
        if name not in static or name == "index.html":
            raise AppError("no such file", 404)
        return Response(static[name], media_type=STATIC_FILES[name], headers=_NO_STORE)

    async def api_info(request: Request) -> Response:
        return _json({"frames": editor.frames, "palette": palette(), "downloads": sorted(DOWNLOADS),
                      "limits": {"max_upload_bytes": limits.max_upload_bytes,
                                 "max_upload_pixels": limits.max_upload_pixels, "max_ops": limits.max_ops},
                      **info})

    async def open_upload(request: Request) -> Response:
        data = await _body(request, limits.max_upload_bytes, "image")
        if not data:
            raise AppError("send the image file as the request body (PNG or JPEG)", 400)
        query = request.query_params
        intrinsics = None
        if any(k in query for k in ("fx", "fy", "cx", "cy")):
            try:
                intrinsics = {k: float(query[k]) for k in ("fx", "fy", "cx", "cy") if k in query}
            except ValueError:
                raise AppError("intrinsics fx, fy, cx, cy must be numbers", 400) from None
        found = await run_in_threadpool(editor.open_upload, data, intrinsics, query.get("name"))
        await run_in_threadpool(editor.scene, found.sid)
        return _json(editor.view(found), 201)

    async def open_frame(request: Request) -> Response:
        body = await _json_body(request, limits.max_request_bytes)
        if not isinstance(body, dict) or set(body) != {"frame"}:
            raise AppError('send {"frame": <index in /api/info frames>}', 400)
        found = await run_in_threadpool(editor.open_frame, body["frame"])
        await run_in_threadpool(editor.scene, found.sid)
        return _json(editor.view(found), 201)

    async def session_view(request: Request) -> Response:
        found = await run_in_threadpool(editor.scene, request.path_params["sid"])
        return _json(editor.view(found))

    async def edit(request: Request) -> Response:
        sid = request.path_params["sid"]
        editor.get(sid)  # 404 before reading a body
        body = await _json_body(request, limits.max_request_bytes)
        found = await run_in_threadpool(editor.edit, sid, body)
        return _json(editor.view(found))

    async def box_at(request: Request) -> Response:
        sid = request.path_params["sid"]
        editor.get(sid)  # 404 before reading a body
        body = await _json_body(request, limits.max_request_bytes)
        return _json(await run_in_threadpool(editor.box_at, sid, body))

    async def input_png(request: Request) -> Response:
        return _png(editor.get(request.path_params["sid"]).input_png)

    async def edited_png(request: Request) -> Response:
        found = editor.get(request.path_params["sid"])
        return _png(found.png, **{"X-Version": str(found.version)})

    async def labels_png(request: Request) -> Response:
        return _png(await run_in_threadpool(editor.labels_png, request.path_params["sid"]))

    async def download(request: Request) -> Response:
        name = request.path_params["name"]
        path = await run_in_threadpool(editor.download, request.path_params["sid"], name)
        return FileResponse(path, media_type=DOWNLOADS[name], filename=name, headers=_NO_STORE)

    async def close(request: Request) -> Response:
        await run_in_threadpool(editor.close, request.path_params["sid"])
        return _json({"closed": request.path_params["sid"]})

    async def app_error(request: Request, exc: Exception) -> Response:
        assert isinstance(exc, UserInputError)
        extra = exc.extra if isinstance(exc, AppError) else {}
        return _json({"error": str(exc), **extra}, exc.status if isinstance(exc, AppError) else 422)

    async def http_error(request: Request, exc: Exception) -> Response:
        assert isinstance(exc, HTTPException)
        return _json({"error": str(exc.detail)}, exc.status_code)

    async def server_error(request: Request, exc: Exception) -> Response:
        if is_disk_full(exc):  # 507 Insufficient Storage, the message naming the file; the server goes on
            log.warning("sdn3d-app: %s %s: %s", request.method, request.url.path, exc)
            return _json({"error": str(exc) if "disk is full" in str(exc) else f"the disk is full: {exc}"}, 507)
        log.error("sdn3d-app: %s %s failed", request.method, request.url.path, exc_info=exc)
        return _json({"error": f"internal error ({type(exc).__name__}); the server's log has the details"}, 500)

    routes = [
        Route("/", page), Route("/static/{name}", static_file), Route("/api/info", api_info),
        Route("/api/open", open_upload, methods=["POST"]), Route("/api/open_frame", open_frame, methods=["POST"]),
        Route("/api/s/{sid}", session_view), Route("/api/s/{sid}", close, methods=["DELETE"]),
        Route("/api/s/{sid}/edit", edit, methods=["POST"]), Route("/api/s/{sid}/box_at", box_at, methods=["POST"]),
        Route("/api/s/{sid}/input.png", input_png),
        Route("/api/s/{sid}/edited.png", edited_png), Route("/api/s/{sid}/labels.png", labels_png),
        Route("/api/s/{sid}/download/{name}", download),
    ]
    middleware = [Middleware(KnownHosts, hosts=hosts or allowed_hosts("127.0.0.1")),
                  Middleware(SameOriginWrites)]
    return Starlette(routes=routes, middleware=middleware,
                     exception_handlers={UserInputError: app_error, HTTPException: http_error, Exception: server_error})
