"""The HTML report renders in headless Chromium with every image loaded, every linked
page exists, and the screenshots of the summary and flat-plate pages are saved."""
import html
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

from support import NARWHAL, ROOT

from harness import browser
from harness.ladder import load_ladder


@unittest.skipUnless(browser.chromium(), "chromium is not installed")
class Render(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        given = os.environ.get("NARWHAL_REPORT_DIR")
        if given:
            cls.report = Path(given)
            cls.tmp = None
        else:
            cls.tmp = Path(tempfile.mkdtemp())
            subprocess.run([sys.executable, str(ROOT / "validation" / "run"), "--tier", "quick", "--rung",
                            "flat_plate_laminar", "--rung", "poiseuille", "--narwhal", str(NARWHAL), "--reports",
                            str(cls.tmp), "--run-id", "r"], check=True, capture_output=True, timeout=900)
            cls.report = cls.tmp / "r"
        cls.doms = {}

    @classmethod
    def dom(cls, page):
        """The page's DOM after load: one Chromium start per page, shared by the tests (the
        tests only read the report; starting the browser is the expensive part)."""
        if page not in cls.doms:
            cls.doms[page] = browser.dump_dom(page)
        return cls.doms[page]

    @classmethod
    def tearDownClass(cls):
        if cls.tmp:
            shutil.rmtree(cls.tmp, ignore_errors=True)

    def pages(self):
        index = self.report / "index.html"
        self.assertTrue(index.exists(), f"no report at {index}")
        links = re.findall(r"href='([^']+\.html)'", index.read_text())
        return [index, self.report / "perf.html"] + [self.report / l for l in sorted(set(links))]

    def test_every_page_exists_and_all_images_load(self):
        pages = self.pages()
        self.assertGreaterEqual(len(pages), 3)
        for page in pages:
            self.assertTrue(page.exists(), f"linked page missing: {page}")
            dom = self.dom(page)
            self.assertIn('data-images="ok"', dom, f"{page}: images did not all load")

    def test_summary_shows_the_whole_ladder_with_the_steps_not_built_yet(self):
        dom = self.dom(self.report / "index.html")
        self.assertIn("The validation ladder", dom)
        for step in load_ladder():
            self.assertIn(html.escape(step.title), dom)
            if step.planned:
                self.assertIn(f"not built yet ({step.planned})", dom)

    def test_one_sided_checks_show_their_bound_not_a_delta(self):
        dom = self.dom(self.report / "index.html")
        one_sided = [c for rj in self.report.glob("*/results.json") for c in json.loads(rj.read_text())["checks"]
                     if c["comparator"] in ("max", "min")]
        if not one_sided:
            self.skipTest("no one-sided check in this report")
        for c in one_sided:
            bound = ("≤ " if c["comparator"] == "max" else "≥ ") + f"{c['tolerance']:.6g}"
            self.assertIn(bound, dom, c["name"])

    def test_every_check_with_a_value_has_its_figure(self):
        for rj in self.report.glob("*/results.json"):
            res = json.loads(rj.read_text())
            dom = self.dom(rj.parent / "index.html")
            for i, c in enumerate(res["checks"]):
                if c.get("computed") is not None:
                    self.assertIn(f'src="check_{i}.png"', dom, f"{res['rung']}: check {i} ({c['name']}) has no figure")

    def test_a_broken_image_is_detected(self):
        bad = self.report / "broken_probe.html"
        bad.write_text((self.report / "index.html").read_text().replace("</h1>", "</h1><img src='nope.png'>"))
        try:
            self.assertIn('data-images="broken:1"', browser.dump_dom(bad))
        finally:
            bad.unlink()

    def test_screenshots_are_saved_with_the_report(self):
        for name in ("summary.png", "flat_plate_laminar.png"):
            png = self.report / "screenshots" / name
            self.assertTrue(png.exists(), png)
            self.assertGreater(png.stat().st_size, 10000, png)
            self.assertEqual(png.read_bytes()[:8], b"\x89PNG\r\n\x1a\n")


if __name__ == "__main__":
    unittest.main()
