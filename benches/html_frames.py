"""Frame time of the HTML report viewer on large meshes, in headless Chromium.

    .venv/bin/python benches/html_frames.py [TRIANGLES ...]   (default 250000 1000000 4000000)

For each size: a closed triangulated torus with 20 holes punched in it, `surfkit eat --html`,
then the page opened in headless Chromium (software WebGL, SwiftShader: no GPU on the bench
machine, so these are upper bounds for a desktop) and timed: file size, time until the first
frame, the median full frame and the median frame while the camera moves (the viewer draws
every k-th triangle then, k chosen from the first frame's time). No peer: MeshLab has no
browser viewer to time in the same run.
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from selenium import webdriver
from selenium.webdriver.chrome.service import Service

REPO = Path(__file__).resolve().parents[1]
CLI = REPO / "target" / "release" / "surfkit"


def torus_ply(path: Path, triangles: int, holes: int = 20) -> None:
    """A torus of about `triangles` triangles (n × m quads split), less `holes` triangles."""
    m = max(8, int(np.sqrt(triangles / 2 / 3)))
    n = max(8, triangles // (2 * m))
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    a, b = 2 * np.pi * i / n, 2 * np.pi * j / m
    x = (3 + np.cos(b)) * np.cos(a)
    y = (3 + np.cos(b)) * np.sin(a)
    z = np.sin(b)
    vertices = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype("<f4")
    v = lambda p, q: (p % n) * m + (q % m)
    p, q = i.ravel(), j.ravel()
    lower = np.stack([v(p, q), v(p + 1, q), v(p + 1, q + 1)], axis=-1)
    upper = np.stack([v(p, q), v(p + 1, q + 1), v(p, q + 1)], axis=-1)
    faces = np.concatenate([lower, upper])
    keep = np.ones(len(faces), dtype=bool)
    keep[np.linspace(0, len(faces) - 1, holes).astype(int)] = False
    faces = faces[keep]
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    records = np.empty(len(faces), dtype=[("n", "u1"), ("v", "<i4", 3)])
    records["n"], records["v"] = 3, faces
    with path.open("wb") as f:
        f.write(header.encode())
        f.write(vertices.tobytes())
        f.write(records.tobytes())


def browser() -> webdriver.Chrome:
    options = webdriver.ChromeOptions()
    options.binary_location = "/usr/bin/chromium"
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-dev-shm-usage",
        "--window-size=1280,800",
        "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader",
    ):
        options.add_argument(arg)
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)


def main() -> None:
    sizes = [int(s) for s in sys.argv[1:]] or [250_000, 1_000_000, 4_000_000]
    print(f"html_frames {time.strftime('%Y-%m-%d')} (headless Chromium, SwiftShader)")
    print("triangles  file MB  first frame s  full frame ms  moving frame ms (every k-th)")
    driver = browser()
    try:
        for size in sizes:
            with tempfile.TemporaryDirectory() as tmp:
                mesh, html = Path(tmp) / "torus.ply", Path(tmp) / "torus.html"
                torus_ply(mesh, size)
                subprocess.run(
                    [str(CLI), "eat", str(mesh), "--html", str(html)],
                    check=False,
                    capture_output=True,
                )
                t0 = time.monotonic()
                driver.get(html.as_uri())
                while not driver.execute_script("return !!(window.surfkit && surfkit.ready)"):
                    time.sleep(0.02)
                first = time.monotonic() - t0
                full = driver.execute_script("return surfkit.measureFrameTime(5, false)")
                moving = driver.execute_script("return surfkit.measureFrameTime(5, true)")
                view = driver.execute_script(
                    "return [surfkit.views[0].triangleCount, surfkit.views[0].movingStep]"
                )
                mb = html.stat().st_size / 1e6
                print(
                    f"{view[0]:>9}  {mb:7.1f}  {first:13.2f}  {full:13.0f}  "
                    f"{moving:8.0f} ({view[1]})"
                )
    finally:
        driver.quit()


if __name__ == "__main__":
    main()
