"""Fixtures of the browser tests: the surfkit CLI built by scripts/test.sh, and Debian's
headless Chromium driven through its chromedriver (WebDriver), with the network off."""

from __future__ import annotations

import os
import shutil
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

REPO = Path(__file__).resolve().parents[2]
MESHES = REPO / "fixtures" / "meshes"
ARTIFACTS = REPO / "target" / "test-artifacts" / "browser"


@pytest.fixture(scope="session")
def cli() -> Path:
    """The release binary the Rust suites built (SURFKIT_BIN overrides it)."""
    path = Path(os.environ.get("SURFKIT_BIN", REPO / "target" / "release" / "surfkit"))
    if not path.exists():
        pytest.fail(f"{path} is missing: build it with cargo build --release first")
    return path


@pytest.fixture(scope="session")
def artifacts() -> Path:
    """Where the tests leave their screenshots."""
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    return ARTIFACTS


def _program(names: list[str]) -> str:
    for name in names:
        found = shutil.which(name)
        if found:
            return found
    pytest.fail(f"none of {names} is installed: scripts/setup.sh installs chromium-driver")


@pytest.fixture(scope="session")
def browser() -> Iterator[webdriver.Chrome]:
    """Headless Chromium (software WebGL through SwiftShader) with the network disabled."""
    options = webdriver.ChromeOptions()
    options.binary_location = _program(["chromium", "chromium-browser"])
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--window-size=1280,800",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
    ):
        options.add_argument(arg)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service(_program(["chromedriver"])), options=options)
    driver.execute_cdp_cmd("Network.enable", {})
    driver.execute_cdp_cmd(
        "Network.emulateNetworkConditions",
        {"offline": True, "latency": 0, "downloadThroughput": -1, "uploadThroughput": -1},
    )
    yield driver
    driver.quit()


def open_report(driver: webdriver.Chrome, path: Path, timeout: float = 60.0) -> None:
    """Loads a report and waits until its views have drawn their first frame."""
    driver.get_log("browser")  # drop what earlier pages logged
    driver.get(path.resolve().as_uri())
    deadline = time.monotonic() + timeout
    while not driver.execute_script("return !!(window.surfkit && window.surfkit.ready)"):
        if time.monotonic() > deadline:
            pytest.fail(f"{path}: the viewer did not draw within {timeout} s")
        time.sleep(0.05)
