"""The settings check and table: one set of solver settings over a rung's runs, and any
setting that differs (or that a run lacks) named."""
import json
import unittest

from support import rung_in_temp_dir

from harness import report
from harness.errors import HarnessError
from harness.extract import Context, extract
from harness.settings import split_settings

RUNG = """
[rung]
title = "t"
tiers = ["quick"]

[[sweep]]
id = "drift"
input = "in.toml"
variable = "flow.drift_angle"
values = [0, 4, 8]

[[check]]
name = "one set of settings"
extract = { kind = "settings_differing" }
comparator = "max"
tolerance = 0
rationale = "because"
"""

SETTINGS = {"turbulence_model": "sst", "cfl_max": 1000.0, "multigrid_levels": 3, "max_iterations": 300}


class SettingsOverARung(unittest.TestCase):
    def setUp(self):
        self.dir, self.rung = rung_in_temp_dir(RUNG)

    def context(self, change=None):
        """The sweep's runs with SETTINGS; `change` maps a run index to the settings it updates
        (a value of None removes the setting)."""
        dirs = {}
        for i, run in enumerate(self.rung.runs):
            settings = dict(SETTINGS)
            for k, v in (change or {}).get(i, {}).items():
                if v is None:
                    settings.pop(k)
                else:
                    settings[k] = v
            d = self.dir / "runs" / run.id
            d.mkdir(parents=True, exist_ok=True)
            (d / "run.json").write_text(json.dumps({"settings": settings}))
            dirs[run.id] = d
        return Context(self.rung, dirs, {rid: {} for rid in dirs})

    def count(self, ctx, **spec):
        return extract(ctx, {"kind": "settings_differing", **spec})

    def test_one_set_of_settings_counts_nothing(self):
        self.assertEqual(self.count(self.context()), 0.0)

    def test_a_tuned_point_and_a_missing_setting_count(self):
        self.assertEqual(self.count(self.context({2: {"cfl_max": 200.0}})), 1.0)
        self.assertEqual(self.count(self.context({1: {"turbulence_model": None}})), 1.0)
        self.assertEqual(self.count(self.context({0: {"cfl_max": 200.0}, 1: {"max_iterations": 150}})), 2.0)

    def test_ignored_settings_may_differ(self):
        ctx = self.context({1: {"max_iterations": 150}})
        self.assertEqual(self.count(ctx, ignore=["max_iterations"]), 0.0)
        with self.assertRaises(HarnessError):
            self.count(ctx, ignore="max_iterations")

    def test_a_single_run_cannot_show_uniformity(self):
        ctx = self.context()
        first = next(iter(ctx.run_dirs))
        with self.assertRaises(HarnessError):
            extract(Context(self.rung, {first: ctx.run_dirs[first]}, {first: {}}),
                    {"kind": "settings_differing"})

    def test_split_and_the_reports_table(self):
        by_run = {"a": dict(SETTINGS), "b": dict(SETTINGS, cfl_max=200.0)}
        shared, differing = split_settings(by_run)
        self.assertEqual(shared["turbulence_model"], "sst")
        self.assertEqual(differing, {"cfl_max": {"a": 1000.0, "b": 200.0}})
        page = report._settings_section(by_run)
        self.assertIn("1 setting(s) differ between the 2 runs: cfl_max", page)
        self.assertIn("b: 200", page)
        self.assertIn("One set of settings for all 2 run(s)", report._settings_section({"a": SETTINGS, "b": SETTINGS}))
        self.assertEqual(report._settings_section({}), "")


if __name__ == "__main__":
    unittest.main()
