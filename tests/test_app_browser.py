"""sdn3d-app in a real browser (Debian's chromium through Selenium): click a car, drag it, turn it, delete another,
undo and redo, download the spec and the picture; the picture changed where the cars were and went and nowhere else,
and the downloaded spec reproduces it bit for bit through sdn3d-edit. Tiny random-weight checkpoints on the real
Virtual KITTI frame, objects from boxes drawn on the page (proposals=boxes).

Without chromium, chromedriver or selenium the tests are skipped, except on CI (CI=true), where that is a failure:
scripts/test.sh installs them."""

from __future__ import annotations

import io
import math
import os
import shlex
import time

import numpy as np
import pytest
from helpers.app_server import REAL_FRAME_ARGS, checkpoint_args, request, serving
from helpers.browser import Page, missing_reason, start_chromium, wait_for_file
from helpers.tiny_models import write_checkpoints
from PIL import Image

from sdn3d.cli.edit import main as edit_main

BOXES = ([466, 203, 666, 333], [704, 194, 917, 305])  # the two near cars of the real frame (input pixels)
_MISSING = missing_reason()
if _MISSING and os.environ.get("CI", "").lower() == "true":
    raise RuntimeError(f"the browser tests cannot run on CI: {_MISSING}")
pytestmark = pytest.mark.skipif(_MISSING is not None, reason=str(_MISSING))


@pytest.fixture(scope="module")
def ckpts(tmp_path_factory):
    return write_checkpoints(tmp_path_factory.mktemp("ckpt"))


@pytest.fixture(scope="module")
def page(ckpts, tmp_path_factory):
    """``(Page, base URL, downloads folder)``: the editor's page in chromium, served from a thread."""
    folder = tmp_path_factory.mktemp("browser")
    downloads = folder / "downloads"
    downloads.mkdir()
    with serving([*checkpoint_args(ckpts), *REAL_FRAME_ARGS, f"output_dir={folder / 'out'}"]) as (base, _):
        driver = start_chromium(downloads)
        try:
            yield Page(driver, base), base, downloads
        finally:
            driver.quit()


def _hull(obj: dict, camera: dict, grow: float = 1.0) -> tuple[float, float, float, float]:
    """The bounding rectangle (input pixels) of an object's projected 3D box (the page's own projection), its
    length and width times ``grow``."""
    (cx, cy, cz), (length, height, width), ry = obj["center"], obj["dims"], obj["ry"]
    length, width = length * grow, width * grow
    us, vs = [], []
    for x in (-0.5, 0.5):
        for y in (-0.5, 0.5):
            for z in (-0.5, 0.5):
                px, py, pz = x * length, y * height, z * width
                X, Y, Z = (math.cos(ry) * px + math.sin(ry) * pz + cx, py + cy,
                           -math.sin(ry) * px + math.cos(ry) * pz + cz)
                us.append(camera["fx"] * X / Z + camera["cx"])
                vs.append(camera["fy"] * Y / Z + camera["cy"])
    return min(us), min(vs), max(us), max(vs)


def _allowed(shape, rects, margin=12, below=0.2) -> np.ndarray:
    """Pixels within ``margin`` of a rectangle, and a band of ``below`` of its height under it (the vacated road's
    old contact shadow, the moved car's new one)."""
    out = np.zeros(shape, bool)
    for x0, y0, x1, y1 in rects:
        y1 = y1 + below * (y1 - y0)
        rows = slice(max(0, int(y0 - margin)), int(math.ceil(y1 + margin)))
        out[rows, max(0, int(x0 - margin)):int(math.ceil(x1 + margin))] = True
    return out


def test_click_drag_turn_delete_undo_download_and_reproduce(page, real_vkitti_frame, tmp_path):
    browser, base, downloads = page
    view = browser.upload(real_vkitti_frame)
    assert view["input"]["width"] == 1242 and view["objects"] == []  # proposals=boxes: nothing until a box is drawn
    for box in BOXES:  # Shift+drag draws a box: the object is fitted from it
        browser.drag((box[0], box[1]), (box[2], box[3]), shift=True)
        browser.wait_idle()
    before = browser.objects()
    assert sorted(before) == [12001, 12002] and all(o["geometry"] for o in before.values()), browser.errors()
    assert len(browser.state()["objects"]) == 2

    browser.click_element("show-labels")  # the semantic map's classes over the picture, with a legend
    browser.js("const c = document.getElementById('compare'); c.value = 50; c.dispatchEvent(new Event('input'))")
    deadline = time.monotonic() + 20
    while not browser.js("return window.sdn3dApp.labels !== null") and time.monotonic() < deadline:
        time.sleep(0.05)
    assert browser.driver.find_element(browser.by.ID, "legend").text != "" and browser.errors() == []
    browser.click_element("show-labels")
    browser.js("const c = document.getElementById('compare'); c.value = 0; c.dispatchEvent(new Event('input'))")

    car, other = before[12001], before[12002]
    browser.click(*car["centre"])
    assert browser.js("return window.sdn3dApp.selected") == 12001
    assert browser.driver.find_element(browser.by.ID, "sel-title").text == "12001 Car"

    start = car["centre"]
    browser.drag(start, (start[0] + 90, start[1] + 12))  # the car slides along the road
    browser.wait_idle()
    ops = browser.state()["ops"]
    assert [o["op"] for o in ops] == ["move"] and ops[0]["id"] == 12001
    assert ops[0]["to"] == pytest.approx([start[0] + 90, start[1] + 12], abs=3)  # whole CSS pixels of a scaled canvas
    moved = browser.objects()[12001]
    assert moved["centre"] == pytest.approx(ops[0]["to"], abs=0.15)  # its 3D centre projects under the pointer

    browser.chord("\ue008", "q")  # Shift+Q: turn 15 degrees
    browser.wait_idle()
    turned = browser.objects()[12001]
    assert browser.state()["ops"][-1] == {"op": "rotate", "id": 12001, "ry_deg": 15}
    assert math.remainder(turned["yaw_deg"] - moved["yaw_deg"] - 15, 360) == pytest.approx(0, abs=0.11)

    browser.click(*other["centre"])
    assert browser.js("return window.sdn3dApp.selected") == 12002
    browser.keys("\ue017")  # Delete
    browser.wait_idle()
    assert 12002 not in browser.objects() and browser.state()["ops"][-1] == {"op": "delete", "id": 12002}
    browser.chord("\ue009", "z")  # Ctrl+Z: the other car is back
    browser.wait_idle()
    assert 12002 in browser.objects() and [o["op"] for o in browser.state()["ops"]] == ["move", "rotate"]
    browser.chord("\ue009", "y")  # Ctrl+Y: and gone again
    browser.wait_idle()
    assert 12002 not in browser.objects()
    assert browser.errors() == []

    final = browser.view()
    browser.click_element("dl-spec")
    spec = wait_for_file(downloads, "spec.yaml")
    assert spec.read_text() == final["spec"] and "{op: \"delete\", id: 12002}" in spec.read_text()
    browser.click_element("dl-png")
    shown = np.asarray(Image.open(wait_for_file(downloads, "edited.png")))
    status, _, served = request(base, "GET", f"/api/s/{final['sid']}/edited.png")
    assert status == 200
    assert np.array_equal(shown, np.asarray(Image.open(io.BytesIO(served))))

    # changed where the cars were and where the first one went, nowhere else
    original = np.asarray(Image.open(real_vkitti_frame).convert("RGB"))
    changed = (shown != original).any(2)
    # the cars' visible masks and 3D boxes before; the first car's 3D box after, and its contact shadow (the floor
    # grown by 10 %, editing.photo); its mask's box carried by the drag (a car whose view hardly turns is drawn from
    # its own mask moved by its box's 2D map, photo.mask_view_deg, and its GrabCut mask reaches a little past the box)
    camera = final["camera"]
    dx, dy = ops[0]["to"][0] - start[0], ops[0]["to"][1] - start[1]
    carried = (car["box"][0] + dx, car["box"][1] + dy, car["box"][2] + dx, car["box"][3] + dy)
    # and the deleted car's footprint grown by half, where its shadow's faint edge is relit (photo.faint_light: the
    # road right of the black car's bumper, 6-27 px past its box, 2 grey levels lighter)
    rects = [car["box"], other["box"], _hull(car, camera), _hull(other, camera), _hull(other, camera, grow=1.5),
             _hull(browser.objects()[12001], camera, grow=1.15), carried]
    allowed = _allowed(changed.shape, rects, margin=16)
    outside = np.argwhere(changed & ~allowed)
    assert changed.any() and not len(outside), (len(outside), outside.min(0), outside.max(0), car["box"],
                                                other["box"], _hull(car, camera), _hull(other, camera))
    x0, y0, x1, y1 = other["box"]
    assert changed[y0:y1, x0:x1].mean() > 0.5  # the deleted car's pixels were filled
    assert not changed[:150].any() and not changed[:, :300].any()  # sky, trees, the left of the road

    # the downloaded spec through the command line the page shows: the same picture, bit for bit
    args = shlex.split(final["command"].split(" && ", 1)[1])[1:]
    args = [a for a in args if not a.startswith(("edits=", "output_dir="))]
    out = tmp_path / "cli"
    assert edit_main([*args, f"edits={spec}", f"output_dir={out}"]) == 0
    assert np.array_equal(np.asarray(Image.open(out / "edited.png")), shown)


def test_a_click_on_a_car_adds_the_box_it_implies(page, real_vkitti_frame, tmp_path):
    """Add object (click): the page asks for the box a click implies, shows it dashed and adds it as a box object,
    which is fitted like a drawn one; the box is near the one a person would draw around that car."""
    browser, _, _ = page
    if browser.view() is None:
        browser.upload(real_vkitti_frame)
    browser.click_element("reset")  # the same file again would not reach the page's file input: start afresh
    browser.wait_idle()
    assert browser.state()["objects"] == [] and browser.view()["objects"] == []
    browser.click_element("add-click")
    browser.click(600, 280)  # the red car
    browser.wait_idle()
    state = browser.state()
    assert len(state["objects"]) == 1, browser.errors()
    box, drawn = state["objects"][0]["box"], BOXES[0]
    assert browser.js("return window.sdn3dApp.implied") == box  # shown as it was added
    inter = (max(0, min(box[2], drawn[2]) - max(box[0], drawn[0]))
             * max(0, min(box[3], drawn[3]) - max(box[1], drawn[1])))
    union = (box[2] - box[0]) * (box[3] - box[1]) + (drawn[2] - drawn[0]) * (drawn[3] - drawn[1]) - inter
    assert inter / union > 0.8, box
    assert [o["geometry"] for o in browser.objects().values()] == [True] and browser.errors() == []
    browser.screenshot(tmp_path / "clicked.png")


def test_the_page_edits_a_copy_refuses_empty_road_and_speaks_its_own_words(page, real_vkitti_frame, tmp_path):
    """Issue 42: before an image is open undo and redo are disabled; the upload is named by its own name; a copy made
    by Duplicate is turned like any car (and stands clear of its original); the dashed clicked box goes with the next
    change; Alt+click on empty road is refused with the reason, adds nothing, and 'Add anyway' adds it; opening the
    camera fields does not wrap the toolbar."""
    from selenium.webdriver.common.action_chains import ActionChains
    from selenium.webdriver.common.keys import Keys

    browser, base, _ = page
    browser.driver.get(base + "/")  # a fresh page: nothing open
    browser.canvas = browser.driver.find_element(browser.by.ID, "view")
    assert browser.js("return ['undo', 'redo', 'reset'].map(i => document.getElementById(i).disabled)") == [True] * 3
    header = browser.js("return document.querySelector('header').getBoundingClientRect().height")
    browser.driver.find_element(browser.by.CSS_SELECTOR, "#camera-box summary").click()
    assert browser.js("return document.querySelector('header').getBoundingClientRect().height") == header
    browser.driver.find_element(browser.by.CSS_SELECTOR, "#camera-box summary").click()
    browser.upload(real_vkitti_frame)
    assert browser.view()["input"]["name"] == real_vkitti_frame.name

    def alt_click(u, v):
        x, y = browser._offset(u, v)
        ActionChains(browser.driver, duration=50).key_down(Keys.ALT).move_to_element_with_offset(browser.canvas, x, y) \
            .click().key_up(Keys.ALT).perform()
        time.sleep(0.2)
        browser.wait_idle()

    alt_click(565, 280)  # the red car
    assert list(browser.objects()) == [12001] and browser.js("return window.sdn3dApp.implied") is not None
    browser.click(565, 280)
    browser.click_element("duplicate")
    browser.wait_idle()
    objects = browser.objects()
    assert list(objects) == [12001, 12002] and browser.errors() == []
    assert browser.js("return window.sdn3dApp.implied") is None  # the dashed box went with the change
    a, b = objects[12001], objects[12002]
    assert math.dist((a["center"][0], a["center"][2]), (b["center"][0], b["center"][2])) > a["dims"][0]  # clear
    browser.click(*b["centre"])
    browser.driver.find_element(browser.by.CSS_SELECTOR, "[data-turn='15']").click()
    browser.wait_idle()
    assert browser.objects()[12002]["yaw_deg"] == pytest.approx(b["yaw_deg"] + 15, abs=0.2), browser.errors()
    assert browser.state()["ops"][-1] == {"op": "rotate", "id": 12002, "ry_deg": 15}
    before = browser.state()
    alt_click(300, 340)  # empty road
    error = browser.js("return document.getElementById('error-text').textContent")
    assert error.startswith("no vehicle at (") and "GrabCut found no object under the click" in error
    assert browser.state() == before and browser.js("return !document.getElementById('anyway').hidden")
    browser.screenshot(tmp_path / "refused.png")
    # (that road box, forced, would take the red car's pixels: GrabCut gives each pixel to the nearest box.) A box
    # drawn in the sky: the edit is refused (nothing added), then added when the user says so.
    browser.drag((560, 30), (680, 90), shift=True)
    time.sleep(0.2)
    browser.wait_idle()
    error = browser.js("return document.getElementById('error-text').textContent")
    assert error.startswith("objects[1] (box [") and "Car): no vehicle there: its bottom edge (row " in error
    assert "is above the horizon (row 187)" in error and "give it force: true" in error and browser.state() == before
    browser.click_element("anyway")
    time.sleep(0.2)
    browser.wait_idle()
    assert browser.state()["objects"][-1].get("force") is True and len(browser.objects()) == 3, browser.errors()
