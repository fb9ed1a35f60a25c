"""``sdn3d-app``: the browser editor. Open an image, click a car, drag it, turn it, recolour or delete it.

Configuration ``conf/app.yaml``: every setting of ``sdn3d-edit`` (``conf/edit.yaml``: ``run=`` or the three
``checkpoints.*``, ``data=... data.root=...`` for frames to pick, ``proposals``, ``photo.*``, ``threads``, ...) plus
the server's own (``host``, default ``127.0.0.1``; ``port``; upload limits; ``output_dir``)::

    sdn3d-app run=outputs/demo                      # prints http://127.0.0.1:8030/ ; Ctrl+C stops it
    sdn3d-app run=outputs/demo proposals=boxes      # a real photo: draw a box around each car to edit
    sdn3d-app run=outputs/demo data=synth data.root=outputs/demo/data

The models load once; each image is de-rendered once (per set of drawn boxes); every interaction applies the
page's whole spec to that scene and draws it (:class:`sdn3d.editing.session.EditSession`, as ``sdn3d-edit``). The
page shows the YAML spec and the ``sdn3d-edit`` command line that reproduce its picture bit for bit; the command
repeats this command line's overrides except the app's own keys (:data:`APP_KEYS`), ``output_dir`` and the input.
docs/EDITOR.md describes the page.

Stopping (Ctrl+C, or SIGTERM): the server finishes the requests under way and says where the sessions' files
(uploads, ``spec.yaml``, downloads: what the page's command lines read) are kept: in ``<output_dir>/sessions/``
until the next ``sdn3d-app`` with the same ``output_dir`` starts, which removes them (a session directory holding a
file the app did not write, such as the output of its ``sdn3d-edit`` command line, is kept and named).

Exit status: 0 stopped (Ctrl+C); 2 bad settings (message on stderr naming the setting; nothing served); 130
interrupted before serving.
"""

from __future__ import annotations

import re
import shutil
import signal
import socket
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from sdn3d.cli._config import compose_config, print_help_if_asked
from sdn3d.cli._errors import run_cli
from sdn3d.errors import InputError

__all__ = ["main", "build_app", "bind", "APP_KEYS", "edit_overrides"]

#: Settings of the app alone (``conf/app.yaml``'s own keys): not repeated on the ``sdn3d-edit`` command line.
APP_KEYS = ("host", "port", "max_upload_bytes", "max_upload_pixels", "max_edit_pixels", "max_request_bytes",
            "max_sessions", "session_idle_s", "open_browser")
#: ``sdn3d-edit`` settings the app sets per image or refuses (the page chooses the image and writes the spec).
PER_IMAGE_KEYS = ("input", "edits", "list", "entry", "frame_size", "output_dir", "overwrite")


def edit_overrides(argv: Sequence[str]) -> list[str]:
    """The overrides of an ``sdn3d-app`` command line that ``sdn3d-edit`` takes as they are (every one but the app's
    own keys, the input, the spec and the output directory), in order."""
    out = []
    for arg in argv:
        key = arg.split("=", 1)[0].lstrip("+~").split(".", 1)[0]
        if key not in APP_KEYS and key not in PER_IMAGE_KEYS:
            out.append(arg)
    return out


def _check_app_settings(cfg: Any, argv: Sequence[str]) -> None:
    """Refuse the ``sdn3d-edit`` settings the page owns, and a bad host or port, naming the setting."""
    given = sorted({a.split("=", 1)[0].lstrip("+~") for a in argv
                    if a.split("=", 1)[0].lstrip("+~").split(".", 1)[0] in PER_IMAGE_KEYS[:5]})
    if given:
        raise InputError(f"{', '.join(given)}: sdn3d-app opens images and writes the spec on its page; give only the "
                         "checkpoints and settings (conf/app.yaml)")
    if not cfg.host:  # host a string, port an integer: the schema (sdn3d.cli._schemas)
        raise InputError(f"host must be an address to listen on (127.0.0.1: this machine only), got {cfg.host!r}")
    if not 0 <= cfg.port <= 65535:
        raise InputError(f"port must be an integer in [0, 65535] (0: a free one), got {cfg.port!r}")


def build_app(cfg: Any, argv: Sequence[str]) -> tuple[Any, Any]:
    """``(Starlette application, Editor)`` of a composed ``conf/app.yaml`` (``argv``: its overrides, which the
    ``sdn3d-edit`` command lines repeat): the models loaded, the dataset's frames listed.

    Raises:
        UserInputError: a bad setting, checkpoint or dataset (named).
    """
    import torch

    from sdn3d.app.editor import AppLimits, Editor
    from sdn3d.app.server import allowed_hosts, create_app
    from sdn3d.cli.edit import (
        check_settings,
        config_record,
        load_models,
        open_input,
        resolve_checkpoints,
    )
    from sdn3d.editing.session import EditSession
    from sdn3d.editing.settings import session_settings
    from sdn3d.io import refuse_unsafe_output_dir

    _check_app_settings(cfg, argv)
    check_settings(cfg)
    limits = AppLimits(max_upload_bytes=cfg.max_upload_bytes, max_upload_pixels=cfg.max_upload_pixels,
                       max_edit_pixels=cfg.max_edit_pixels,
                       max_request_bytes=cfg.max_request_bytes, max_sessions=cfg.max_sessions, max_ops=cfg.max_ops,
                       session_idle_s=cfg.session_idle_s)
    refuse_unsafe_output_dir(cfg.output_dir)
    if cfg.threads is not None:
        torch.set_num_threads(int(cfg.threads))
    records = []
    if cfg.get("data") is not None:
        from sdn3d.data.sources import SourceConfig, read_source

        records = read_source(SourceConfig.from_mapping(cfg.data))
        if not records:
            raise InputError(f"no frames found under data.root={cfg.data.root!r}")
    checkpoints = resolve_checkpoints(cfg, records[0] if records else None)
    models, code_bank = load_models(cfg, checkpoints)
    settings = session_settings(cfg, checkpoints)
    session = EditSession(models, code_bank, settings, cache_size=2 * limits.max_sessions)
    passed = edit_overrides(argv)

    def open_image(given: dict[str, Any], key: str) -> Any:
        # sdn3d-edit's opening of its input (the same camera rules, the same reader, the same errors) on this
        # server's own settings with the page's input.* values: what the command line the page shows composes
        chosen = cfg.copy()
        for name, value in given.items():
            chosen.input[name] = value
        return open_input(chosen, None, key=key)[0]

    editor = Editor(session, cfg.output_dir, open_image, [r.key for r in records], passed,
                    {"checkpoints": checkpoints, "config": config_record(cfg)}, limits)
    info = {"proposals": settings.proposals, "appearance": settings.appearance,
            "box_objects": True, "dataset": cfg.data.root if records else None}
    return create_app(editor, info, allowed_hosts(str(cfg.host))), editor


def bind(host: str, port: int) -> socket.socket:
    """A listening socket on ``host:port`` (port 0: a free one).

    Raises:
        InputError: the address cannot be used (in use, not this machine's), naming host and port.
    """
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((host, port))
        sock.listen(64)
    except OSError as exc:
        sock.close()
        raise InputError(f"cannot listen on host={host} port={port}: {exc.strerror or exc} (give port=<another> or "
                         "port=0 for a free one)") from None
    return sock


#: What the app writes in a session's directory (:mod:`sdn3d.app.editor`); anything else there is the user's.
_SESSION_FILES = re.compile(r"input\.(png|jpg)|spec\.yaml|edited\.png|edit\.json|edited_scene\.glb|command\.txt"
                            r"|\..+\.tmp")
_SID = re.compile(r"[A-Za-z0-9_-]{16,64}")


def remove_earlier_sessions(sessions_dir: Path) -> tuple[int, list[Path]]:
    """Remove the session directories an earlier ``sdn3d-app`` left in ``sessions_dir`` (unreachable now: a
    session lives in the server's memory). Returns ``(how many were removed, those kept)``: a directory holding
    anything the app does not write (the output of its ``sdn3d-edit`` command line, a user's file, a link) is kept."""
    removed, kept = 0, []
    if not sessions_dir.is_dir():
        return 0, []
    for entry in sorted(sessions_dir.iterdir()):
        if entry.is_symlink() or not entry.is_dir() or not _SID.fullmatch(entry.name):
            kept.append(entry)
            continue
        inside = list(entry.iterdir())
        if any(f.is_symlink() or not f.is_file() or not _SESSION_FILES.fullmatch(f.name) for f in inside):
            kept.append(entry)
            continue
        shutil.rmtree(entry)
        removed += 1
    return removed, kept


def _stopped_note(editor: Any) -> str:
    """What stopping keeps, and where (the module doc)."""
    sessions = sorted(p for p in editor.sessions_dir.iterdir() if p.is_dir()) if editor.sessions_dir.is_dir() else []
    if not sessions:
        return "sdn3d-app: stopped; no session files are left"
    return (f"sdn3d-app: stopped; the files of {len(sessions)} session(s) (uploads, spec.yaml, downloads: what the "
            f"page's command lines read) are kept in {editor.sessions_dir} until the next sdn3d-app with "
            f"output_dir={editor.output_dir} starts, which removes them")


def _main(argv: list[str]) -> int:
    import uvicorn

    cfg = compose_config(argv, "app")
    app, editor = build_app(cfg, argv)  # the settings checked (output_dir included) before anything is removed
    removed, kept = remove_earlier_sessions(editor.sessions_dir)
    if removed:
        print(f"sdn3d-app: removed {removed} session director{'y' if removed == 1 else 'ies'} of an earlier run from "
              f"{editor.sessions_dir}", file=sys.stderr)
    if kept:
        print(f"sdn3d-app: kept {len(kept)} entr{'y' if len(kept) == 1 else 'ies'} of an earlier run holding files "
              f"it did not write: {', '.join(str(k) for k in kept[:5])}", file=sys.stderr)
    sock = bind(str(cfg.host), int(cfg.port))
    host, port = sock.getsockname()[:2]
    shown = f"[{host}]" if ":" in host else host
    url = f"http://{shown}:{port}/"
    server = uvicorn.Server(uvicorn.Config(app, log_level="warning", access_log=False, lifespan="off"))

    def stop(signum: int, frame: Any) -> None:  # SIGINT and SIGTERM: the same clean stop
        server.should_exit = True

    # Ours before the line that says it serves: a Ctrl+C right after it, before uvicorn's own handlers are in, stops
    # the server as cleanly as a later one (raising KeyboardInterrupt there could land inside logging's locks, and
    # asyncio's own handler would only cancel the starting server and leave it serving). uvicorn puts these back
    # and raises the signal again when it stops: the flag again, nothing raised.
    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    try:
        print(f"sdn3d-app: serving {url} (sessions in {editor.output_dir}; Ctrl+C stops)", flush=True)
        if cfg.host not in ("127.0.0.1", "localhost", "::1"):
            print(f"sdn3d-app: warning: host={cfg.host} makes the editor reachable from other machines; it has no "
                  "login", file=sys.stderr)
        if cfg.open_browser:
            import webbrowser

            webbrowser.open(url)
        server.run(sockets=[sock])  # uvicorn stops on SIGINT / SIGTERM (its handlers while it runs, ours before)
    finally:
        print(_stopped_note(editor), file=sys.stderr, flush=True)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Console entry point: ``sdn3d-app [overrides...]``; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if print_help_if_asked(argv, __doc__, "app"):
        return 0
    try:
        return run_cli("app", _main, argv)
    except KeyboardInterrupt:  # before serving (loading the models): nothing was served
        print("sdn3d-app: interrupted before serving", file=sys.stderr)
        return 128 + signal.SIGINT


if __name__ == "__main__":
    sys.exit(main())
