"""The HTML report renders in headless Chromium with every image loaded, every linked
page exists, and the screenshots of the summary and flat-plate pages are saved."""
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
            dom = browser.dump_dom(page)
            self.assertIn('data-images="ok"', dom, f"{page}: images did not all load")

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
