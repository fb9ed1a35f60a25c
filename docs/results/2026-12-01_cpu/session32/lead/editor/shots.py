# Session 32 copy (unchanged) of session 30 copy (unchanged) of session 29 copy of session 28 copy of session 25 lead editor/shots.py (run with the fresh CI clone's venv, PYTHONPATH=<clone>/src);
# weights RUN (argv 3) instead of session 21's w0, lost with the machine.
# ruff: noqa: E402, E501, E702
"""shots.py REPO OUT RUN: sdn3d-app in chromium on the real frame with two boxes (session 10's editor_shots.py, session
11's demo weights): the red car recoloured blue, the black car turned -90 degrees (Shift+E six times), then the black
car deleted (Delete key); a screenshot after each."""
import sys
import tempfile
from pathlib import Path

REPO, OUT, RUN = Path(sys.argv[1]), Path(sys.argv[2]), sys.argv[3]
sys.path.insert(0, str(REPO / "tests"))
from helpers.app_server import serving
from helpers.browser import Page, start_chromium

FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = ([466, 203, 666, 333], [704, 194, 917, 305])
OUT.mkdir(parents=True, exist_ok=True)
with tempfile.TemporaryDirectory(prefix="sdn3d-app-shots-") as tmp:
    with serving([f"run={RUN}", "proposals=boxes", "threads=2", f"output_dir={tmp}/out"]) as (base, _):
        driver = start_chromium(Path(tmp), width=1560, height=900)
        try:
            page = Page(driver, base)
            page.upload(FRAME)
            for box in BOXES:
                page.drag((box[0], box[1]), (box[2], box[3]), shift=True)
                page.wait_idle()
            cars = page.objects()
            red, black = cars[12001], cars[12002]
            page.click(*red["centre"]); page.wait_idle()
            driver.execute_script("document.querySelector('#palette button[data-color=\"blue\"]').click()")
            page.wait_idle()
            page.screenshot(OUT / "editor_red_recoloured_blue.png")
            page.click_element("undo"); page.wait_idle()  # the recolour undone
            page.click(*red["centre"]); page.wait_idle()
            for _ in range(6):  # Shift+E: -15 degrees each
                page.chord("\ue008", "e"); page.wait_idle()
            page.screenshot(OUT / "editor_red_turned_-90.png")
            page.click(*black["centre"]); page.wait_idle()
            for _ in range(6):  # Shift+E: -15 degrees each
                page.chord("\ue008", "e"); page.wait_idle()
            page.screenshot(OUT / "editor_black_turned_-90.png")
            page.keys("\ue017"); page.wait_idle()  # Delete
            page.screenshot(OUT / "editor_black_deleted.png")
            print("spec:\n" + page.view()["spec"])
            print("errors on the page:", page.errors())
        finally:
            driver.quit()
