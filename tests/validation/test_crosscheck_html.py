"""``report.html`` beside ``report.md``: the same text and tables, the pictures, and the
mechanism as an interactive 3D view, checked in a real headless browser (Debian's chromium,
driven by Playwright) with every network request refused."""

import html
import json
import shutil

import numpy as np
import pytest

from dem.scenes import voussoir_arch
from validation.crosscheck.cli import main as crosscheck_main

BROWSERS = ("chromium", "chromium-browser")


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    """A cross-check of a 12-voussoir arch under a lateral load (limit analysis and static
    DEM: a mechanism, a pushover, joint states)."""
    tmp = tmp_path_factory.mktemp("html")
    path = tmp / "arch.json"
    voussoir_arch(2.0, 0.2, 12, live_direction=None).to_json(path)
    out = tmp / "out"
    args = ["--live", "x", "--quick", "--methods", "limit,dem", "--out", str(out)]
    assert crosscheck_main([str(path), *args]) == 0
    return out


def test_html_has_the_reports_text_tables_pictures_and_view(report):
    page = (report / "report.html").read_text()
    data = json.loads((report / "report.json").read_text())
    for check in data["checks"]:  # every line of the verdict table
        assert f"<td>{html.escape(check['name'], quote=False)}</td>" in page
    for name in ("pushover.png", "mechanism.png", "interface_states.png"):
        assert f'src="{name}"' in page and (report / name).exists()
    assert '<iframe src="mechanism_3d.html"' in page
    for text in (page, (report / "mechanism_3d.html").read_text()):
        assert '<script src="http' not in text and '<link href="http' not in text


def _browser() -> str:
    for name in BROWSERS:
        found = shutil.which(name)
        if found:
            return found
    pytest.skip(
        "no chromium on this machine (scripts/setup.sh installs Debian's chromium; "
        "a browser download of Playwright's own cannot be fetched here)"
    )


def test_report_opens_in_a_headless_browser_offline(report, tmp_path):
    """Every picture loads, the 3D view's canvas draws something (not one colour), and the
    page asks for nothing outside the folder."""
    executable = _browser()
    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed")
    outside = []

    def only_files(route):
        if route.request.url.startswith(("file:", "data:", "blob:")):
            route.continue_()
        else:
            outside.append(route.request.url)
            route.abort()

    with sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch(
            executable_path=executable,
            args=["--no-sandbox", "--use-angle=swiftshader", "--enable-unsafe-swiftshader"],
        )
        try:
            page = browser.new_page(viewport={"width": 1200, "height": 900})
            page.route("**/*", only_files)
            page.goto((report / "report.html").as_uri())
            page.wait_for_load_state("load")
            images = page.evaluate(
                "Array.from(document.images).map(i => [i.complete, i.naturalWidth])"
            )
            view = page.frame_locator("iframe").locator("canvas").first
            view.wait_for(state="visible", timeout=30_000)
            page.wait_for_timeout(1500)  # vtk.js draws after the scene is parsed
            shot = tmp_path / "view.png"
            page.locator("iframe").screenshot(path=str(shot))
        finally:
            browser.close()
    assert len(images) == 3 and all(done and width > 0 for done, width in images), images
    import matplotlib.image

    pixels = matplotlib.image.imread(shot)[..., :3]
    coloured = np.ptp(pixels, axis=-1) > 0.2  # the blocks' viridis colours, not grey or white
    assert coloured.mean() > 0.01, "the 3D view drew no coloured blocks"
    assert not outside, outside
