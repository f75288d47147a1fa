"""Every kind of HTML report opened in headless Chromium with the network off: the page
loads nothing from outside, logs no error, draws a non-blank picture, lists every flaw of
the JSON report, and centres the camera on a flaw when its entry is clicked."""

from __future__ import annotations

import io
import json
import math
import subprocess
from pathlib import Path

import pytest
from PIL import Image
from selenium import webdriver
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

from conftest import MESHES, open_report

BACKGROUND = (48, 48, 54)


def run(cli: Path, *args: object) -> subprocess.CompletedProcess[str]:
    return subprocess.run([str(cli), *map(str, args)], capture_output=True, text=True, check=False)


def console_errors(driver: webdriver.Chrome) -> list[str]:
    return [e["message"] for e in driver.get_log("browser") if e["level"] == "SEVERE"]


def check_page_health(driver: webdriver.Chrome, name: str, artifacts: Path) -> None:
    """No console error, nothing fetched, and every view's canvas drew a picture."""
    assert console_errors(driver) == [], name
    fetched = driver.execute_script(
        "return performance.getEntriesByType('resource').map(e => e.name)"
    )
    assert fetched == [], f"{name} fetched {fetched}"
    canvases = driver.find_elements(By.CSS_SELECTOR, ".view canvas")
    assert canvases, name
    for k, canvas in enumerate(canvases):
        rgb = Image.open(io.BytesIO(canvas.screenshot_as_png)).convert("RGB").tobytes()
        pixels = [rgb[i : i + 3] for i in range(0, len(rgb), 3)]
        drawn = sum(
            1 for p in pixels if max(abs(a - b) for a, b in zip(p, BACKGROUND, strict=True)) > 12
        )
        assert drawn > 0.01 * len(pixels), f"{name}: view {k} is blank ({drawn} pixels)"
    driver.save_screenshot(str(artifacts / f"{name}.png"))


def camera(driver: webdriver.Chrome) -> dict:
    return driver.execute_script("return JSON.parse(JSON.stringify(window.surfkit.camera))")


FLAWED = ["octagonal_pocket.ply", "catmark_nonman_edge100.obj", "joined_tetrahedra.obj"]


@pytest.mark.parametrize("mesh", FLAWED)
def test_eat_report_lists_every_flaw_and_centres_on_it(
    cli: Path, browser: webdriver.Chrome, artifacts: Path, tmp_path: Path, mesh: str
) -> None:
    html = tmp_path / "report.html"
    done = run(cli, "eat", MESHES / mesh, "--json", "--html", html)
    assert done.returncode in (0, 3), done.stderr
    flaws = json.loads(done.stdout)["report"]["flaws"]
    assert flaws, f"{mesh} has flaws to show"
    open_report(browser, html)
    name = "eat_" + Path(mesh).stem
    check_page_health(browser, name, artifacts)
    entries = browser.find_elements(By.CSS_SELECTOR, "[data-flaw-index]")
    assert [int(e.get_attribute("data-flaw-index")) for e in entries] == list(range(len(flaws)))
    legend = browser.find_element(By.ID, "legend").text
    kinds = {f["kind"] for f in flaws}
    for kind in kinds:
        assert kind.replace("_", " ") in legend
    for index in sorted({0, len(flaws) - 1, len(flaws) // 2}):
        browser.find_element(By.ID, "reset-view").click()
        before = camera(browser)
        entry = browser.find_element(By.CSS_SELECTOR, f'[data-flaw-index="{index}"]')
        browser.execute_script("arguments[0].scrollIntoView()", entry)
        entry.click()
        after = camera(browser)
        flaw = flaws[index]
        assert after != before
        # the camera looks at the flaw's point (the page stores it less the view origin)
        origin = browser.execute_script("return window.surfkit.views[0].spec.origin")
        target = [t + o for t, o in zip(after["target"], origin, strict=True)]
        scale = max(abs(x) for x in flaw["position"]) + 1.0
        position = flaw["position"]
        assert all(abs(t - p) <= 1e-9 * scale for t, p in zip(target, position, strict=True))
        details = browser.find_element(By.ID, "flaw-details").text
        assert flaw["description"] in details
        assert flaw["suggested_fix"] in details
    assert console_errors(browser) == []
    browser.save_screenshot(str(artifacts / f"{name}_selected.png"))


def test_fair_report_shows_both_surfaces_one_scale_and_the_log(
    cli: Path, browser: webdriver.Chrome, artifacts: Path, tmp_path: Path
) -> None:
    mesh, html = tmp_path / "tubes.obj", tmp_path / "fair.html"
    assert run(cli, "gen", "tubes", "-o", mesh).returncode == 0
    done = run(cli, "fair", mesh, "-o", tmp_path / "out.obj", "--html", html, "--json")
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout)["report"]
    open_report(browser, html)
    check_page_health(browser, "fair_tubes", artifacts)
    names = [e.text for e in browser.find_elements(By.CSS_SELECTOR, ".view .name")]
    assert names == ["before", "after"]
    # the log: one point per iteration and the start, |g|/|g0| (g0 the input's) ending at
    # the report's
    paths = browser.find_elements(By.CSS_SELECTOR, "#plot svg path")
    assert len(paths) == 2
    plot = browser.execute_script("return window.surfkit.page.plot")
    gradient = plot["series"][0]["y"]
    assert len(gradient) == len(report["newton"]["iterations"]) + 1
    assert math.isclose(
        gradient[-1],
        report["final_gradient_norm"] / report["initial_gradient_norm"],
        rel_tol=1e-12,
    )
    # isophotes and reflection lines change the picture
    canvas = browser.find_elements(By.CSS_SELECTOR, ".view canvas")[1]
    shaded = canvas.screenshot_as_png
    for mode, label in (("1", "isophotes"), ("2", "reflection_lines")):
        Select(browser.find_element(By.ID, "shading-mode")).select_by_value(mode)
        browser.execute_script("return new Promise(r => requestAnimationFrame(() => r()))")
        assert canvas.screenshot_as_png != shaded, label
        browser.save_screenshot(str(artifacts / f"fair_tubes_{label}.png"))
    assert console_errors(browser) == []


def test_limit_report_colour_bar_ends_are_the_written_curvature_range(
    cli: Path, browser: webdriver.Chrome, artifacts: Path, tmp_path: Path
) -> None:
    html = tmp_path / "limit.html"
    out = tmp_path / "limit.ply"
    done = run(cli, "limit", MESHES / "catmark_torus.obj", "-o", out, "--html", html, "--json")
    assert done.returncode == 0, done.stderr
    h = json.loads(done.stdout)["mean_curvature"]
    open_report(browser, html)
    check_page_health(browser, "limit_torus", artifacts)
    bar = browser.execute_script("return window.surfkit.page.colour_bar")
    assert bar["min"] == h["min"] and bar["max"] == h["max"]
    shown_max = browser.find_element(By.CSS_SELECTOR, "#colour-bar .max").text
    shown_min = browser.find_element(By.CSS_SELECTOR, "#colour-bar .min").text
    assert math.isclose(float(shown_max), h["max"], rel_tol=1e-3, abs_tol=1e-12)
    assert math.isclose(float(shown_min), h["min"], rel_tol=1e-3, abs_tol=1e-12)


def test_fill_report_shows_data_points_and_the_hole_border(
    cli: Path, browser: webdriver.Chrome, artifacts: Path, tmp_path: Path
) -> None:
    csv = tmp_path / "wave.csv"
    rows = ["u,v,x,y,z"]
    for i in range(40):
        for j in range(40):
            u, v = (i + 0.5) / 40, (j + 0.5) / 40
            if 4 * (u - 0.5) ** 2 + 9 * (v - 0.5) ** 2 > 0.25:
                rows.append(f"{u},{v},{u},{v},{0.3 * math.sin(3 * u) * math.cos(2 * v)}")
    csv.write_text("\n".join(rows) + "\n")
    html = tmp_path / "fill.html"
    done = run(cli, "fill", csv, "--hole", "ellipse:0.5,0.5,4,9,0.25", "--html", html)
    assert done.returncode == 0, done.stderr
    open_report(browser, html)
    check_page_health(browser, "fill_wave", artifacts)
    legend = browser.find_element(By.ID, "legend").text
    assert f"data points ({len(rows) - 1})" in legend
    assert "hole border" in legend


def test_demo_writes_one_report_per_section_and_lists_them_first(
    cli: Path, browser: webdriver.Chrome, artifacts: Path, tmp_path: Path
) -> None:
    out = tmp_path / "demo"
    done = run(cli, "demo", "--out", out)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert str(out / "index.html") in lines[0]
    listed = [Path(line.split()[0]) for line in lines[1:6]]
    assert all(p.suffix == ".html" for p in listed)
    index = (out / "index.html").read_text()
    for page in listed:
        assert page.is_file()
        assert str(page.relative_to(out)) in index
        open_report(browser, page)
        check_page_health(browser, "demo_" + page.stem, artifacts)
