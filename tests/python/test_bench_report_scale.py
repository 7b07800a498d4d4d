"""The report at the size of a real evaluation, in headless Chromium: a 40-task run in which every task
failed and was filmed keeps its HTML under the size bound (failure videos linked from thumbnails, not
inlined) and draws every task's force trace; three such runs side by side fit a 1280 px window, with a
letter per run and a legend (a screenshot is taken)."""
from __future__ import annotations

import math
import shutil
from pathlib import Path

import pytest

from bench_cli import bench
from culinarycut.bench.store import ResultStore
from stored_runs import rows

TASKS = 40
COPIES = 10  # the 4 filmed tasks of the real run, stored under 10 names each
# A 364-task failing run's page must stay under 20 MB: the same share per task.
MAX_HTML_BYTES_PER_TASK = 20e6 / 364
WINDOW = (1280, 900)
FAILING_SUITE = """name = "failing"
description = "four short draft tasks the noop policy fails"
trials = 1
max_episode_steps = 30
quality = "draft"

[[tasks]]
food = "cucumber"
state = "ratio"
ratio = [0.3, 0.7]
side = ["left", "right"]
"""


@pytest.fixture(scope="module")
def failing_run(tmp_path_factory, address) -> Path:
    """A real run of 4 filmed failures (noop), grown to 40 tasks by storing each episode under 10 task names
    with its trace and a copy of its video, as a run of 40 such tasks stores them."""
    folder = tmp_path_factory.mktemp("failing")
    suite = folder / "failing.toml"
    suite.write_text(FAILING_SUITE)
    run = folder / "run"
    bench("run", str(suite), "--policy", "noop", "--record-failures", "--server", address, "--workers", "2",
          "--out", str(run), "--no-progress")
    real = rows(run)
    assert len(real) == 4 and all(r["outcome"] == "failure" and r["video"] for r in real)
    with ResultStore(run) as store:
        for copy in range(1, COPIES):
            for row in real:
                task = f"{row['task']}/copy-{copy}"
                video = f"videos/{task.replace('/', '_')}_trial0.gif"
                shutil.copyfile(run / row["video"], run / video)
                assert store.record({**row, "task": task, "video": video}, store.trace(row["task"], row["trial"]))
    assert len(rows(run)) == TASKS
    return run


def open_page(page: Path, screenshot: Path | None = None) -> dict:
    """What Chromium shows at 1280 x 900: image states, the widths that overflow, table headers, links."""
    from selenium import webdriver
    options = webdriver.ChromeOptions()
    for flag in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                 f"--window-size={WINDOW[0]},{WINDOW[1]}", "--force-device-scale-factor=1"):
        options.add_argument(flag)
    browser = webdriver.Chrome(options=options)
    try:
        browser.get(page.as_uri())
        shown = browser.execute_script("""
            const tables = Array.from(document.querySelectorAll('table'));
            return {
              images: Array.from(document.images).map(i => [i.complete, i.naturalWidth, i.alt]),
              viewport: window.innerWidth,
              page_width: document.documentElement.scrollWidth,
              overflowing_tables: tables.filter(t => t.scrollWidth > t.clientWidth + 1).length,
              tables: tables.length,
              first_headers: Array.from(tables[0].querySelectorAll('th')).map(th => th.textContent),
              first_column: Array.from(tables[0].querySelectorAll('tbody tr')).map(tr => tr.cells[0].textContent),
              video_links: Array.from(document.querySelectorAll('figure.video > a')).map(a => a.href),
            };""")
        if screenshot is not None:
            browser.save_screenshot(str(screenshot))
    finally:
        browser.quit()
    return shown


def test_a_40_task_failing_run_stays_small_and_shows_every_task(failing_run, tmp_path):
    bench("report", str(failing_run), "--out", str(tmp_path))
    page = tmp_path / "report.html"
    size = page.stat().st_size
    print(f"report.html of {TASKS} failed, filmed tasks: {size / 1e6:.2f} MB")
    assert size < TASKS * MAX_HTML_BYTES_PER_TASK, size
    assert "data:image/gif" not in page.read_text()  # videos are files beside the page
    shown = open_page(page)
    assert all(done and width > 0 for done, width, _ in shown["images"]), shown["images"]
    forces = [alt for _, _, alt in shown["images"] if alt.startswith("Force at the wrist")]
    pages = math.ceil(TASKS / 12)
    assert forces == [f"Force at the wrist, every trial: tasks {12 * i + 1}-{min(TASKS, 12 * i + 12)} of {TASKS}"
                      for i in range(pages)]
    assert len(shown["video_links"]) == TASKS  # the first failure of every task
    for link in shown["video_links"]:
        assert Path(link.removeprefix("file://")).is_file(), link
    markdown = (tmp_path / "report.md").read_text()
    assert markdown.count("](report_files/force_time") == pages


def test_three_runs_side_by_side_fit_1280_px_with_a_letter_and_a_legend(failing_run, tmp_path):
    runs = []
    for name in ("first", "second", "third"):
        shutil.copytree(failing_run, tmp_path / name)
        runs.append(str(tmp_path / name))
    bench("report", *runs, "--out", str(tmp_path / "report"))
    screenshot = tmp_path / "report_1280.png"
    shown = open_page(tmp_path / "report" / "report.html", screenshot)
    assert shown["viewport"] == WINDOW[0]
    assert shown["page_width"] <= shown["viewport"] and shown["overflowing_tables"] == 0, shown
    assert shown["first_headers"][:3] == ["run", "policy @ server", "folder"]
    assert shown["first_column"] == ["A", "B", "C"]  # the legend: each letter's policy, server and folder
    markdown = (tmp_path / "report" / "report.md").read_text()
    assert "| task | A success | A rate | A 95 % CI | B success |" in markdown
    assert len(set(shown["video_links"])) == 3 * TASKS  # each run's own videos, none overwritten by another's
    from PIL import Image
    with Image.open(screenshot) as image:
        darkest, brightest = image.convert("L").getextrema()
        assert image.width == WINDOW[0] and brightest - darkest > 100  # a page was drawn, not a blank window
