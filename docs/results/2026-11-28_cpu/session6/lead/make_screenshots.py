"""Screenshots of sdn3d-app in chromium with the demo's weights (issue 30): a selected car, one being dragged (the
live outline), the dragged one after release, and the other one deleted. The same page driving as the browser test
(tests/helpers/browser.py, tests/helpers/app_server.py).

    .venv/bin/python docs/results/2026-11-26_cpu/issue30/make_screenshots.py            # needs outputs/demo

Writes selected.png, dragging.png, dragged.png, deleted.png beside this file.
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

HERE = Path('/tmp/s6data/lead/shots')
REPO = Path('/work/wt/lead-final')
sys.path.insert(0, str(REPO / "tests"))

from helpers.app_server import serving  # noqa: E402
from helpers.browser import Page, start_chromium  # noqa: E402

FRAME = REPO / "tests" / "data" / "0006_30-deg-right_00043.png"
BOXES = ([466, 203, 666, 333], [704, 194, 917, 305])


def main() -> int:
    with tempfile.TemporaryDirectory(prefix="sdn3d-app-shots-") as tmp:
        overrides = ["run=/tmp/s5data/lead/demo", "proposals=boxes", "threads=2", f"output_dir={tmp}/out"]
        with serving(overrides) as (base, _):
            driver = start_chromium(Path(tmp), width=1560, height=760)
            try:
                page = Page(driver, base)
                page.upload(FRAME)
                for box in BOXES:
                    page.drag((box[0], box[1]), (box[2], box[3]), shift=True)
                    page.wait_idle()
                cars = page.objects()
                car, other = cars[12001], cars[12002]
                page.click(*car["centre"])
                page.screenshot(HERE / "selected.png")

                from selenium.webdriver.common.action_chains import ActionChains

                start, end = car["centre"], (car["centre"][0] - 150, car["centre"][1] + 25)
                (x0, y0), (x1, y1) = page._offset(*start), page._offset(*end)
                ActionChains(driver, duration=50).move_to_element_with_offset(page.canvas, x0, y0).click_and_hold() \
                    .move_to_element_with_offset(page.canvas, (x0 + x1) / 2, (y0 + y1) / 2) \
                    .move_to_element_with_offset(page.canvas, x1, y1).perform()
                page.screenshot(HERE / "dragging.png")  # the mouse still held: the outline follows it
                ActionChains(driver).release().perform()
                page.wait_idle()
                page.chord("\ue008", "e")  # Shift+E: turn by -15 degrees
                page.wait_idle()
                page.screenshot(HERE / "dragged.png")

                page.click(*other["centre"])
                page.keys("\ue017")
                page.wait_idle()
                page.screenshot(HERE / "deleted.png")
                print("spec:\n" + page.view()["spec"])
                print("command: " + page.view()["command"])
                print("errors on the page:", page.errors())
            finally:
                driver.quit()
    return 0


if __name__ == "__main__":
    sys.exit(main())
