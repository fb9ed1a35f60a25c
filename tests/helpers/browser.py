"""Driving sdn3d-app's page in Debian's chromium through Selenium (the browser tests and the screenshot script of
docs/results/2026-11-26_cpu/issue30/). Selenium is pointed at the system's ``chromium`` and ``chromedriver``
(``apt-get install chromium chromium-driver``; Selenium's own browser downloads are not reachable)."""

from __future__ import annotations

import os
import shutil
import time
from pathlib import Path
from typing import Any

CHROMIUM = ("chromium", "chromium-browser", "google-chrome")
CHROMEDRIVER = ("chromedriver",)


def _which(names: tuple[str, ...], extra: tuple[str, ...] = ()) -> str | None:
    for name in names:
        found = shutil.which(name)
        if found:
            return found
    return next((p for p in extra if Path(p).is_file()), None)


def browser_paths() -> tuple[str, str] | None:
    """``(chromium, chromedriver)`` executables, or None when either is missing."""
    chromium = _which(CHROMIUM, ("/usr/bin/chromium",))
    driver = _which(CHROMEDRIVER, ("/usr/bin/chromedriver", "/usr/lib/chromium/chromedriver"))
    return (chromium, driver) if chromium and driver else None


def missing_reason() -> str | None:
    """Why the browser tests cannot run here (None: they can)."""
    try:
        import selenium  # noqa: F401
    except ImportError:
        return "selenium is not installed (pip install -e '.[browser]'; scripts/test.sh does)"
    if browser_paths() is None:
        return "chromium and chromedriver are not installed (apt-get install chromium chromium-driver)"
    return None


def start_chromium(downloads: Path, width: int = 1700, height: int = 1000) -> Any:
    """A headless chromium whose downloads go to ``downloads``."""
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    chromium, driver = browser_paths()
    options = webdriver.ChromeOptions()
    options.binary_location = chromium
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
                f"--window-size={width},{height}", "--hide-scrollbars", "--force-device-scale-factor=1"):
        options.add_argument(arg)
    options.add_experimental_option("prefs", {"download.default_directory": str(downloads),
                                              "download.prompt_for_download": False})
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    return webdriver.Chrome(service=Service(driver), options=options)


class Page:
    """The editor's page in a browser: actions in the input image's pixels, waits for the server's answers."""

    def __init__(self, driver: Any, base: str) -> None:
        from selenium.webdriver.common.by import By

        self.driver, self.base, self.by = driver, base, By
        driver.get(base + "/")
        self.canvas = driver.find_element(By.ID, "view")

    def js(self, script: str, *args: Any) -> Any:
        return self.driver.execute_script(script, *args)

    def wait_idle(self, timeout: float = 120.0) -> None:
        """Until no request is running and a view is shown."""
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if self.js("const a = window.sdn3dApp; return a.view !== null && a.inFlight === 0 && !a.pending"):
                return
            time.sleep(0.03)
        raise TimeoutError("the page did not finish its requests")

    def upload(self, path: Path) -> dict:
        self.driver.find_element(self.by.ID, "file").send_keys(str(path))
        time.sleep(0.1)
        self.wait_idle()
        return self.view()

    def view(self) -> dict:
        return self.js("return window.sdn3dApp.view")

    def state(self) -> dict:
        return self.js("const a = window.sdn3dApp; return a.history[a.index]")

    def objects(self) -> dict[int, dict]:
        return {o["id"]: o for o in self.view()["objects"]}

    def _offset(self, u: float, v: float) -> tuple[float, float]:
        """Selenium's pointer offset (from the canvas' centre, CSS pixels) of the input pixel ``(u, v)``."""
        width, height, cw, ch = self.js("const r = arguments[0].getBoundingClientRect();"
                                        "return [r.width, r.height, arguments[0].width, arguments[0].height]",
                                        self.canvas)
        return u * width / cw - width / 2, v * height / ch - height / 2

    def _chain(self) -> Any:
        from selenium.webdriver.common.action_chains import ActionChains

        return ActionChains(self.driver, duration=50)

    def click(self, u: float, v: float) -> None:
        x, y = self._offset(u, v)
        self._chain().move_to_element_with_offset(self.canvas, x, y).click().perform()

    def drag(self, start: tuple[float, float], end: tuple[float, float], shift: bool = False, steps: int = 6) -> None:
        """Press at ``start``, move in ``steps`` to ``end``, release (with Shift: draw a box)."""
        from selenium.webdriver.common.keys import Keys

        (x0, y0), (x1, y1) = self._offset(*start), self._offset(*end)
        chain = self._chain()
        if shift:
            chain.key_down(Keys.SHIFT)
        chain.move_to_element_with_offset(self.canvas, x0, y0).click_and_hold()
        for k in range(1, steps + 1):
            chain.move_to_element_with_offset(self.canvas, x0 + (x1 - x0) * k / steps, y0 + (y1 - y0) * k / steps)
        chain.release()
        if shift:
            chain.key_up(Keys.SHIFT)
        chain.perform()

    def keys(self, *keys: str) -> None:
        """Keys to the focused canvas (a click gives it the focus; sending to the element would click its middle)."""
        self._chain().send_keys(*keys).perform()

    def chord(self, modifier: str, key: str) -> None:
        self._chain().key_down(modifier).send_keys(key).key_up(modifier).perform()

    def click_element(self, element_id: str) -> None:
        self.driver.find_element(self.by.ID, element_id).click()

    def screenshot(self, path: Path) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        self.driver.save_screenshot(str(path))

    def errors(self) -> list[str]:
        """The page's console errors (network 404s of favicons excluded) and its error box."""
        logs = [e["message"] for e in self.driver.get_log("browser") if e["level"] == "SEVERE"]
        shown = self.driver.find_element(self.by.ID, "error").text
        return logs + ([shown] if shown else [])


def wait_for_file(folder: Path, name: str, timeout: float = 30.0) -> Path:
    """A downloaded file once complete (chromium writes ``<name>.crdownload`` first)."""
    deadline = time.monotonic() + timeout
    path = folder / name
    while time.monotonic() < deadline:
        if path.is_file() and not (folder / f"{name}.crdownload").exists():
            return path
        time.sleep(0.05)
    raise TimeoutError(f"{name} was not downloaded to {folder} (found {os.listdir(folder)})")
