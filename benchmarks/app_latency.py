"""sdn3d-app's interaction latency through its HTTP interface, the server's memory, and one whole sdn3d-edit call.

What it does: starts ``python -m sdn3d.cli.app <overrides> port=0`` as a child process, opens an image (default: the
real Virtual KITTI frame in tests/data, 1242x375), draws the boxes given (real photos: ``proposals=boxes``), then
makes ``--n`` interactions of each kind, each the page's own request pair: ``POST /api/s/<sid>/edit`` with the new
state, then ``GET edited.png`` (the picture the page draws). The time of that pair is what a person waits between
releasing the mouse and seeing the picture (the page's own decoding and drawing, a few ms, is not in it).

Kinds (each from the state with only the boxes, the targets varied so every interaction is a new state):
move (a car to another road point), rotate (by 5..175 degrees), distance (zoom on the ground), recolour (the palette
in turn), delete (either car), duplicate, undo (back to a state drawn before), compound (move + turn + delete of the
other car: an accumulated spec), and add object (a new box: a de-render with the GrabCut mask and 3D fit; --n-boxes).

Then the ``sdn3d-edit`` command line the app shows for the last state is run ``--cli-runs`` times as a subprocess
(start to exit), and its edited.png compared with the app's. The server's peak RSS is its ``VmHWM`` at the end.

    python benchmarks/app_latency.py --app run=outputs/demo proposals=boxes threads=2 \\
        --box 466 203 666 333 --box 704 194 917 305

Prints a table (median and 90th percentile per kind, ms) and JSON (``--json``).
"""

from __future__ import annotations

import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request
from pathlib import Path
from typing import Any

REPO = Path(__file__).resolve().parents[1]
COLORS = ["red", "blue", "green", "yellow", "white", "black", "silver", "orange", "purple", "brown"]


def _request(base: str, method: str, path: str, body: Any = None, content_type: str = "application/json") -> Any:
    data = body if body is None or isinstance(body, bytes) else json.dumps(body).encode()
    req = urllib.request.Request(base + path, data=data, method=method, headers={"Content-Type": content_type})
    try:
        with urllib.request.urlopen(req, timeout=600) as response:
            payload = response.read()
            return json.loads(payload) if response.headers.get_content_type() == "application/json" else payload
    except urllib.error.HTTPError as exc:
        raise RuntimeError(f"{method} {path}: {exc.code} {exc.read()[:300]!r}") from None


def _start(overrides: list[str], out: Path) -> tuple[subprocess.Popen, str, float]:
    cmd = [sys.executable, "-m", "sdn3d.cli.app", *overrides, "port=0", f"output_dir={out}"]
    proc = subprocess.Popen(cmd, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    started = time.perf_counter()
    for line in proc.stdout:
        if "serving http" in line:
            return proc, line.split("serving ", 1)[1].split()[0].rstrip("/"), time.perf_counter() - started
    raise RuntimeError(f"sdn3d-app did not start: {proc.stderr.read()[-2000:]}")


def _peak_rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024
    return float("nan")


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    k = (len(ordered) - 1) * q
    lo, hi = int(k), min(int(k) + 1, len(ordered) - 1)
    return ordered[lo] + (ordered[hi] - ordered[lo]) * (k - lo)


def _states(kind: str, n: int, boxes: list[dict], cars: dict[int, dict]) -> list[dict]:
    """``n`` states of one kind of interaction (module doc); ``cars``: the view's objects by id."""
    first, second = sorted(cars)[:2] if len(cars) > 1 else (sorted(cars)[0], None)
    u, v = cars[first]["centre"]
    out = []
    for i in range(n):
        dx, dy = -120 + 240 * ((i * 7) % n) / max(n - 1, 1), 25 * ((i * 3) % 5 - 2) / 2
        if kind == "move":
            ops = [{"op": "move", "id": first, "to": [round(u + dx, 1), round(v + dy, 1)]}]
        elif kind == "rotate":
            ops = [{"op": "rotate", "id": first, "ry_deg": float((5 + 7 * i) % 175 + 5) * (-1) ** i}]
        elif kind == "distance":
            ops = [{"op": "zoom", "id": first, "zoom": round(0.8 + 0.45 * ((i * 7) % n) / max(n - 1, 1), 4),
                    "on_ground": True}]
        elif kind == "recolour":
            ops = [{"op": "recolor", "id": first if i % 2 == 0 or second is None else second,
                    "color": COLORS[i % len(COLORS)]}]
        elif kind == "delete":
            ops = [{"op": "delete", "id": first if i % 2 == 0 or second is None else second}]
        elif kind == "duplicate":
            ops = [{"op": "duplicate", "id": first, "to": [round(u + 150 + dx / 2, 1), round(v + dy, 1)]}]
        elif kind == "compound":
            ops = [{"op": "move", "id": first, "to": [round(u + dx, 1), round(v + dy, 1)]},
                   {"op": "rotate", "id": first, "ry_deg": float(10 + (i * 13) % 150)}]
            if second is not None:
                ops.append({"op": "delete", "id": second})
        else:
            raise ValueError(kind)
        out.append({"objects": boxes, "ops": ops})
    return out


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--app", nargs="+", default=["run=outputs/demo", "proposals=boxes", "threads=2"],
                        help="sdn3d-app overrides (the checkpoints and settings)")
    parser.add_argument("--image", type=Path, default=REPO / "tests" / "data" / "0006_30-deg-right_00043.png")
    parser.add_argument("--box", type=int, nargs=4, action="append", default=None,
                        help="a box x0 y0 x1 y1 (input pixels) around an object to add (proposals=boxes)")
    parser.add_argument("--n", type=int, default=50, help="interactions of each kind")
    parser.add_argument("--n-boxes", type=int, default=5, help="'add object' interactions (each a de-render)")
    parser.add_argument("--cli-runs", type=int, default=5, help="whole sdn3d-edit calls timed")
    parser.add_argument("--json", type=Path, default=None, help="also write the figures here")
    args = parser.parse_args(argv)
    boxes = [{"box": list(b), "class": "Car"} for b in (args.box or [])]
    kinds = ["move", "rotate", "distance", "recolour", "delete", "duplicate", "undo", "compound"]

    with tempfile.TemporaryDirectory(prefix="sdn3d-app-bench-") as tmp:
        load_before = os.getloadavg()
        proc, base, startup_s = _start(args.app, Path(tmp) / "out")
        try:
            t0 = time.perf_counter()
            view = _request(base, "POST", "/api/open", args.image.read_bytes(), "image/png")
            open_s = time.perf_counter() - t0
            sid = view["sid"]
            t0 = time.perf_counter()
            view = _request(base, "POST", f"/api/s/{sid}/edit", {"objects": boxes, "ops": []})
            first_derender_s = time.perf_counter() - t0
            cars = {o["id"]: o for o in view["objects"] if o["geometry"]}
            if not cars:
                raise RuntimeError("no object with 3D geometry to edit (give --box around a car with proposals=boxes)")
            times: dict[str, list[float]] = {k: [] for k in kinds}
            server: dict[str, dict[str, list[float]]] = {k: {} for k in kinds}
            last_state = None

            def interact(kind: str, state: dict) -> None:
                nonlocal last_state
                t = time.perf_counter()
                answer = _request(base, "POST", f"/api/s/{sid}/edit", state)
                _request(base, "GET", f"/api/s/{sid}/edited.png")
                times[kind].append(1000 * (time.perf_counter() - t))
                for key, value in answer["timings_ms"].items():
                    if key != "derender_ms":
                        server[kind].setdefault(key, []).append(value)
                last_state = state

            for kind in kinds:
                if kind == "undo":  # back and forth between two states drawn before: every cache warm
                    seen = _states("compound", 2, boxes, cars)
                    for state in seen:
                        interact("compound", state)
                    times["compound"].clear()
                    server["compound"].clear()
                    for i in range(args.n):
                        interact("undo", seen[i % 2])
                    continue
                for state in _states(kind, args.n, boxes, cars):
                    interact(kind, state)
            box_times = []
            if boxes and args.n_boxes:
                for i in range(args.n_boxes):
                    extra = {"box": [100 + 10 * i, 190, 190 + 10 * i, 240], "class": "Car"}
                    t = time.perf_counter()
                    _request(base, "POST", f"/api/s/{sid}/edit", {"objects": [*boxes, extra], "ops": []})
                    _request(base, "GET", f"/api/s/{sid}/edited.png")
                    box_times.append(1000 * (time.perf_counter() - t))
                _request(base, "POST", f"/api/s/{sid}/edit", last_state)
            final = _request(base, "GET", f"/api/s/{sid}")
            app_png = _request(base, "GET", f"/api/s/{sid}/download/edited.png")
            rss_mb = _peak_rss_mb(proc.pid)
        finally:
            proc.terminate()
            proc.wait(30)

        # the whole sdn3d-edit call the page shows (start to exit), and whether it draws the same picture
        command = final["command"].split(" && ", 1)[1]
        cli_args = shlex.split(command)[1:]
        cli_out = Path(tmp) / "cli"
        cli_args = [a for a in cli_args if not a.startswith("output_dir=")] + [f"output_dir={cli_out}"]
        cli_times = []
        for _ in range(args.cli_runs):
            t = time.perf_counter()
            subprocess.run([sys.executable, "-m", "sdn3d.cli.edit", *cli_args], cwd=REPO, check=True,
                           capture_output=True)
            cli_times.append(time.perf_counter() - t)
        import io

        import numpy as np
        from PIL import Image

        same = bool(np.array_equal(np.asarray(Image.open(cli_out / "edited.png")),
                                   np.asarray(Image.open(io.BytesIO(app_png)))))
        load_after = os.getloadavg()

    rows = {k: {"n": len(v), "median_ms": statistics.median(v), "p90_ms": _percentile(v, 0.9),
                "max_ms": max(v), "server_median_ms": {s: round(statistics.median(x), 1) for s, x in server[k].items()}}
            for k, v in times.items() if v}
    if box_times:
        rows["add object (box)"] = {"n": len(box_times), "median_ms": statistics.median(box_times),
                                    "p90_ms": _percentile(box_times, 0.9), "max_ms": max(box_times),
                                    "server_median_ms": {}}
    result = {"what": "sdn3d-app: POST edit + GET edited.png per interaction (mouse release to picture, less the "
                      "page's decoding)", "image": str(args.image), "image_size": [view["input"]["width"],
                                                                                  view["input"]["height"]],
              "app_overrides": args.app, "boxes": boxes, "startup_s": round(startup_s, 2),
              "open_s": round(open_s, 2), "first_derender_s": round(first_derender_s, 2), "kinds": rows,
              "server_peak_rss_mb": round(rss_mb, 1),
              "sdn3d_edit_call_s": {"runs": [round(t, 2) for t in cli_times],
                                    "median": round(statistics.median(cli_times), 2) if cli_times else None,
                                    "same_picture_as_the_app": same, "command": "sdn3d-edit " + " ".join(cli_args)},
              "load_average_before_after": [round(load_before[0], 2), round(load_after[0], 2)],
              "cpus": os.cpu_count(), "torch_threads": next((a.split("=")[1] for a in args.app
                                                             if a.startswith("threads=")), "default")}
    print(f"sdn3d-app latency, {result['image_size'][0]}x{result['image_size'][1]} input "
          f"({Path(args.image).name}), overrides: {' '.join(args.app)}")
    print(f"start-up {startup_s:.1f} s (models loaded), open {open_s:.2f} s, first de-render with "
          f"{len(boxes)} box(es) {first_derender_s:.2f} s")
    print(f"{'kind':<18}{'n':>4}{'median ms':>11}{'p90 ms':>9}{'max ms':>9}  server medians (ms)")
    for kind, row in rows.items():
        stages = ", ".join(f"{k.removesuffix('_ms')} {v:.0f}" for k, v in row["server_median_ms"].items())
        print(f"{kind:<18}{row['n']:>4}{row['median_ms']:>11.0f}{row['p90_ms']:>9.0f}{row['max_ms']:>9.0f}  {stages}")
    print(f"server peak RSS (VmHWM): {rss_mb:.0f} MB")
    cli = result["sdn3d_edit_call_s"]
    print(f"whole sdn3d-edit call (subprocess, start to exit) x{len(cli_times)}: median {cli['median']} s "
          f"(runs {cli['runs']}); same edited.png as the app: {same}")
    print(f"load average (1 min) before / after: {result['load_average_before_after']} on {os.cpu_count()} CPUs")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result, indent=2) + "\n")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
