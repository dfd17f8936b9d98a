"""Malformed rung files give errors that name the file and the key."""
import tempfile
import textwrap
import unittest
from pathlib import Path

import support  # noqa: F401

from harness.casefile import load_rung
from harness.errors import HarnessError
from harness.extract import Context
from harness.reference import ReferenceFile

GOOD = """
[rung]
title = "t"
tiers = ["quick"]

[[run]]
id = "a"
input = "in.toml"

[[check]]
name = "c"
extract = { kind = "run_json", run = "a", field = "iterations" }
reference = { file = "x.csv", column = "v" }
comparator = "abs"
tolerance = 1.0
rationale = "because"
"""


class RungFiles(unittest.TestCase):
    def write(self, text):
        d = Path(tempfile.mkdtemp()) / "myrung"
        d.mkdir()
        (d / "in.toml").write_text("")
        (d / "case.toml").write_text(textwrap.dedent(text))
        return d / "case.toml"

    def error(self, text):
        path = self.write(text)
        msg = self.error_of(path)
        self.assertIn(str(path), msg)
        return msg

    def error_of(self, path):
        with self.assertRaises(HarnessError) as cm:
            load_rung(path)
        return str(cm.exception)

    def test_set_values_go_back_to_toml_inline_tables_included(self):
        # A run's `set` reaches narwhal as --set key=<TOML>: a list of inline tables (tanks of
        # [[motion.ballast]]) comes back as the same value.
        import tomllib
        text = GOOD.replace('input = "in.toml"', 'input = "in.toml"\nset = { "motion.ballast" = '
                            '[{ mass = 1.5e-5, tank = [0.3, 0.0, 0.0] }, { mass = 2e-5, tank = [-0.3, 0.0, 0.0] }], '
                            '"grid.configuration" = "full" }')
        rung = load_rung(self.write(text))
        sets = rung.runs[0].set
        self.assertEqual(tomllib.loads("v = " + sets["motion.ballast"])["v"],
                         [{"mass": 1.5e-5, "tank": [0.3, 0.0, 0.0]}, {"mass": 2e-5, "tank": [-0.3, 0.0, 0.0]}])
        self.assertEqual(tomllib.loads("v = " + sets["grid.configuration"])["v"], "full")

    def test_misspelled_extractor_key_is_named_with_a_suggestion(self):
        # x_mx = 0.9 used to be ignored, and the whole plate compared.
        msg = self.error(GOOD.replace('field = "iterations" }',
                                      'field = "iterations" }\n').replace(
            'extract = { kind = "run_json", run = "a", field = "iterations" }',
            'extract = { kind = "surface", run = "a", group = "plate", y = "cf_x", x_mx = 0.9 }'))
        self.assertIn("check[0].extract.x_mx", msg)
        self.assertIn("did you mean 'check[0].extract.x_max'", msg)

    def test_misspelled_key_of_a_nested_extraction_is_named(self):
        msg = self.error(GOOD.replace(
            'extract = { kind = "run_json", run = "a", field = "iterations" }',
            'extract = { kind = "ratio", a = { kind = "run_json", run = "a", field = "x" }, '
            'b = { kind = "run_json", run = "a", feild = "y" } }'))
        self.assertIn("check[0].extract.b.feild", msg)

    def test_unknown_extractor_kind_lists_the_valid_ones(self):
        msg = self.error(GOOD.replace('kind = "run_json"', 'kind = "run_jsn"'))
        self.assertIn("check[0].extract.kind", msg)
        self.assertIn("run_json", msg)

    def test_misspelled_reference_key_is_named(self):
        msg = self.error(GOOD.replace('column = "v"', 'colum = "v"'))
        self.assertIn("check[0].reference.colum", msg)
        self.assertIn("did you mean 'check[0].reference.column'", msg)

    def test_option_the_comparator_does_not_take_is_named(self):
        msg = self.error(GOOD.replace('rationale = "because"', 'rationale = "because"\noptions = { pair = 2 }'))
        self.assertIn("check[0].options.pair", msg)

    def test_extractor_reading_an_undeclared_key_is_a_harness_bug(self):
        from harness.schema import Declared
        spec = Declared({"kind": "run_json", "run": "a", "field": "iterations"})
        self.assertEqual(spec.get("field"), "iterations")
        with self.assertRaises(HarnessError) as cm:
            spec.get("column")
        self.assertIn("harness bug", str(cm.exception))

    def test_good_file_loads(self):
        rung = load_rung(self.write(GOOD))
        self.assertEqual(rung.name, "myrung")
        self.assertEqual(rung.checks[0].tiers, ("quick",))

    def test_reported_quantities_load_and_their_keys_are_checked(self):
        report = ('\n[[report]]\nname = "drag at 10 kn"\nunit = "N"\nextract = { kind = "dimensional", run = "a", '
                  'of = { kind = "history_last", column = "body_cfx" }, density = 998.1, speed = 5.1, area = 19.0 }\n')
        rung = load_rung(self.write(GOOD + report))
        self.assertEqual([(q.name, q.unit, q.tiers) for q in rung.reported], [("drag at 10 kn", "N", ("quick",))])
        msg = self.error(GOOD + report.replace("column =", "colum ="))
        self.assertIn("report[0].extract.of.colum", msg)
        msg = self.error(GOOD + report.replace('unit = "N"', 'units = "N"'))
        self.assertIn("unknown key 'report[0].units'", msg)

    def test_pictures_name_a_known_kind_and_run(self):
        pic = '\n[[picture]]\nkind = "axial"\nrun = "a"\ntitle = "Cf"\ncolumn = "cf_signed"\n'
        rung = load_rung(self.write(GOOD + pic))
        self.assertEqual((rung.pictures[0].kind, rung.pictures[0].column, rung.pictures[0].tiers),
                         ("axial", "cf_signed", ("quick",)))
        self.assertIn("picture[0].kind", self.error(GOOD + pic.replace('"axial"', '"contour"')))
        self.assertIn("unknown run 'b'", self.error(GOOD + pic.replace('run = "a"', 'run = "b"')))
        msg = self.error(GOOD + pic + 'reference = { file = "x.csv", x = "a", yy = "b" }\n')
        self.assertIn("picture[0].reference.yy", msg)

    def test_azimuthal_pictures_need_their_stations_and_a_known_run_beside(self):
        pic = '\n[[picture]]\nkind = "azimuthal"\nrun = "a"\ntitle = "Cp"\nstations = [0.5, 0.8]\n'
        rung = load_rung(self.write(GOOD + pic))
        self.assertEqual(rung.pictures[0].stations, [0.5, 0.8])
        self.assertIn("picture[0].stations", self.error(GOOD + pic.replace("stations = [0.5, 0.8]\n", "")))
        self.assertIn("picture[0].stations", self.error(GOOD + pic.replace("[0.5, 0.8]", '["mid"]')))
        self.assertIn("picture[0].beside", self.error(GOOD + pic + 'beside = "peer"\n'))

    def test_time_history_pictures_name_the_file_they_draw_from(self):
        pic = '\n[[picture]]\nkind = "time_history"\nrun = "a"\ntitle = "v"\ncolumn = "motion:vertical_velocity"\n'
        self.assertEqual(load_rung(self.write(GOOD + pic)).pictures[0].column, "motion:vertical_velocity")
        self.assertIn("picture[0].column", self.error(GOOD + pic.replace('"motion:', '"history:')))
        self.assertIn("picture[0].column", self.error(GOOD + pic.replace('"motion:vertical_velocity"', '"u"')))

    def test_wake_strips_name_known_later_runs_and_only_they_take_them(self):
        pic = '\n[[picture]]\nkind = "wake_strip"\nrun = "a"\ntitle = "wake"\nthen = ["a"]\n'
        self.assertEqual(load_rung(self.write(GOOD + pic)).pictures[0].then, ["a"])
        self.assertIn("unknown run 'b'", self.error(GOOD + pic.replace('then = ["a"]', 'then = ["b"]')))
        self.assertIn("picture[0].then", self.error(GOOD + pic.replace('"wake_strip"', '"axial"')))

    def test_a_sweep_expands_into_one_run_per_value(self):
        sweep = ('\n[[sweep]]\nid = "drift"\ninput = "in.toml"\nvariable = "flow.drift_angle"\n'
                 'values = [-4, 0, 2.5]\nset = { "grid.configuration" = "bare" }\nmax_iterations = 50\n')
        rung = load_rung(self.write(GOOD + sweep))
        self.assertEqual([(s.id, s.variable, s.values, s.run_ids) for s in rung.sweeps],
                         [("drift", "flow.drift_angle", (-4.0, 0.0, 2.5), ("drift_m4", "drift_0", "drift_2p5"))])
        points = [r for r in rung.runs if r.id in rung.sweeps[0].run_ids]
        self.assertEqual([(r.id, r.max_iterations, r.tiers) for r in points],
                         [("drift_m4", 50, ("quick",)), ("drift_0", 50, ("quick",)), ("drift_2p5", 50, ("quick",))])
        self.assertEqual(points[0].set, {"grid.configuration": '"bare"', "flow.drift_angle": "-4.0"})
        self.assertIn("sweep[0].values", self.error(GOOD + sweep.replace("[-4, 0, 2.5]", "[]")))
        self.assertIn("sweep[0].values", self.error(GOOD + sweep.replace("[-4, 0, 2.5]", "[1, 1.0]")))
        self.assertIn("sweep[0].values", self.error(GOOD + sweep.replace("[-4, 0, 2.5]", '["4"]')))
        self.assertIn("sweep[0].variable", self.error(GOOD + sweep.replace('"flow.drift_angle"', '"drift"')))
        self.assertIn("sweep[0].set", self.error(GOOD + sweep.replace('"grid.configuration"', '"flow.drift_angle"')))
        self.assertIn("sweep[0].input", self.error(GOOD + sweep.replace('input = "in.toml"', 'input = "no.toml"')))
        self.assertIn("unknown key 'sweep[0].value'", self.error(GOOD + sweep + "value = 1\n"))
        self.assertIn("run ids must be unique", self.error(GOOD.replace('id = "a"', 'id = "drift_0"') + sweep))
        self.assertIn("sweep ids must be unique", self.error(GOOD + sweep + sweep.replace("[-4, 0, 2.5]", "[8]")))
        # Every point may continue one run's restart (a converged start); like repeats it.
        continued = sweep + 'restart_from = "a"\n'
        rung = load_rung(self.write(GOOD + continued + '\n[[sweep]]\nid = "again"\nlike = "drift"\nvalues = [6]\n'))
        self.assertEqual({r.id: r.restart_from for r in rung.runs if r.id != "a"},
                         {"drift_m4": "a", "drift_0": "a", "drift_2p5": "a", "again_6": "a"})
        self.assertIn("restart_from names unknown run 'b'", self.error(GOOD + sweep + 'restart_from = "b"\n'))

    def test_a_sweep_like_another_repeats_its_setup_with_its_own_values_and_added_overrides(self):
        sweep = ('\n[[sweep]]\nid = "drift"\ninput = "in.toml"\nvariable = "flow.drift_angle"\n'
                 'values = [-4, 0, 4]\nset = { "grid.coarsen" = 2, "grid.configuration" = "bare" }\n'
                 'max_iterations = 50\nranks = 2\n')
        medium = '\n[[sweep]]\nid = "drift_medium"\nlike = "drift"\nvalues = [-2, 2]\nset = { "grid.coarsen" = 1 }\n'
        rung = load_rung(self.write(GOOD + sweep + medium))
        self.assertEqual([(s.id, s.variable, s.values) for s in rung.sweeps],
                         [("drift", "flow.drift_angle", (-4.0, 0.0, 4.0)),
                          ("drift_medium", "flow.drift_angle", (-2.0, 2.0))])
        run = next(r for r in rung.runs if r.id == "drift_medium_m2")
        self.assertEqual((run.set, run.max_iterations, run.ranks, run.input.name),
                         ({"grid.coarsen": "1", "grid.configuration": '"bare"', "flow.drift_angle": "-2.0"}, 50, 2,
                          "in.toml"))
        self.assertIn("sweep[1].like", self.error(GOOD + sweep + medium.replace('"drift"', '"yaw"')))
        self.assertIn("sweep[0].like", self.error(GOOD + medium + sweep))
        self.assertIn("sweep[1].set", self.error(GOOD + sweep + medium.replace('"grid.coarsen"', '"flow.drift_angle"')))

    def test_a_sweep_s_unsteady_points_go_on_in_physical_time_by_one_rule_that_like_repeats(self):
        sweep = ('\n[[sweep]]\nid = "drift"\ninput = "in.toml"\nvariable = "flow.drift_angle"\n'
                 'values = [0, 12]\nmax_iterations = 50\nranks = 2\n'
                 '[sweep.unsteady]\nforce_span = 1e-3\ndiscard = 2\n'
                 'set = { "time.scheme" = "bdf2", "time.step" = 0.02, "time.steps" = 400 }\n')
        medium = '\n[[sweep]]\nid = "fine"\nlike = "drift"\nvalues = [4]\nset = { "grid.scale" = 0.5 }\n'
        rung = load_rung(self.write(GOOD + sweep + medium))
        unsteady = rung.sweeps[0].unsteady
        self.assertEqual((unsteady.force_span, unsteady.discard, unsteady.run_ids), (1e-3, 2.0, ("drift_0_time",
                                                                                              "drift_12_time")))
        self.assertEqual(rung.sweeps[1].unsteady.run_ids, ("fine_4_time",))
        later = next(r for r in rung.runs if r.id == "fine_4_time")
        self.assertEqual((later.restart_from, later.when_unsteady, later.ranks, later.max_iterations),
                         ("fine_4", 1e-3, 2, 0))
        self.assertEqual(later.set, {"grid.scale": "0.5", "flow.drift_angle": "4.0", "time.scheme": '"bdf2"',
                                     "time.step": "0.02", "time.steps": "400"})
        self.assertIn("missing required key", self.error(GOOD + sweep.replace("discard = 2\n", "")))
        self.assertIn("'sweep[0].unsteady.set': expected the dual-time settings",
                      self.error(GOOD + sweep.replace('"time.scheme" = "bdf2", "time.step" = 0.02, "time.steps" = 400',
                                                      '"solver.cfl_max" = 4')))
        self.assertIn("expected force_span > 0", self.error(GOOD + sweep.replace("force_span = 1e-3", "force_span = 0.0")))
        self.assertIn("unknown key 'sweep[0].unsteady.discrad'",
                      self.error(GOOD + sweep.replace("discard = 2", "discard = 2\ndiscrad = 1")))
        # One rule for several rungs: the table in a file of its own.
        case = self.write(GOOD)
        rule = sweep[sweep.index("[sweep.unsteady]") + len("[sweep.unsteady]\n"):]
        (case.parent / "rule.toml").write_text(rule)
        by_file = sweep[:sweep.index("[sweep.unsteady]")] + 'unsteady = "rule.toml"\n'
        case.write_text(textwrap.dedent(GOOD + by_file))
        self.assertEqual(load_rung(case).sweeps[0].unsteady.set["time.steps"], "400")
        (case.parent / "rule.toml").write_text(rule.replace("discard = 2", "discard = 2\ndiscrad = 1"))
        self.assertIn("rule.toml: unknown key 'discrad'", self.error_of(case))
        case.write_text(textwrap.dedent(GOOD + by_file.replace("rule.toml", "none.toml")))
        self.assertIn("key 'sweep[0].unsteady': cannot read", self.error_of(case))

    def test_a_family_members_spacing_is_a_number_or_its_cell_count(self):
        fam = GOOD.replace('input = "in.toml"\n', 'input = "in.toml"\nfamily = "f"\nh = "cells"\n', 1)
        run = load_rung(self.write(fam)).runs[0]
        self.assertEqual(run.h, "cells")
        with tempfile.TemporaryDirectory() as d:
            (Path(d) / "run.json").write_text('{"cells": 125000}')
            ctx = Context(load_rung(self.write(fam)), {"a": Path(d)}, {})
            self.assertAlmostEqual(ctx.grid_spacing(run), 0.02, places=14)
        with tempfile.TemporaryDirectory() as d:
            ctx = Context(load_rung(self.write(fam)), {"a": Path(d)}, {})
            with self.assertRaisesRegex(HarnessError, "cell count"):
                ctx.grid_spacing(run)
        msg = self.error(fam.replace('h = "cells"', 'h = "cell"'))
        self.assertIn("run[0].h", msg)
        self.assertIn('"cells"', msg)

    def test_misspelled_key_is_named_with_a_suggestion(self):
        msg = self.error(GOOD.replace("tolerance = 1.0", "tolerence = 1.0\ntolerance = 1.0"))
        self.assertIn("unknown key 'check[0].tolerence'", msg)
        self.assertIn("did you mean 'check[0].tolerance'", msg)

    def test_missing_rationale(self):
        msg = self.error(GOOD.replace('rationale = "because"', ""))
        self.assertIn("check[0].rationale", msg)
        self.assertIn("missing required key", msg)

    def test_wrong_type(self):
        msg = self.error(GOOD.replace("tolerance = 1.0", 'tolerance = "tight"'))
        self.assertIn("check[0].tolerance", msg)
        self.assertIn("expected a numeric tolerance", msg)

    def test_unknown_comparator_lists_the_valid_ones(self):
        msg = self.error(GOOD.replace('comparator = "abs"', 'comparator = "close"'))
        self.assertIn("unknown comparator 'close'", msg)
        self.assertIn("profile_rms", msg)

    def test_unknown_tier(self):
        msg = self.error(GOOD.replace('tiers = ["quick"]', 'tiers = ["weekly"]'))
        self.assertIn("rung.tiers", msg)

    def test_missing_solver_input(self):
        msg = self.error(GOOD.replace('input = "in.toml"', 'input = "nope.toml"'))
        self.assertIn("run[0].input", msg)
        self.assertIn("does not exist", msg)

    def test_syntax_error(self):
        msg = self.error("[rung\n")
        self.assertIn("TOML syntax error", msg)


class ReferenceFiles(unittest.TestCase):
    def setUp(self):
        self.root = Path(tempfile.mkdtemp())
        (self.root / "r.csv").write_text("# Source: test\n# units: none\na,b\n1,2\n3,4\n")
        (self.root / "noheader.csv").write_text("a,b\n1,2\n")

    def test_columns_and_header(self):
        ref = ReferenceFile(self.root, "r.csv")
        self.assertEqual(list(ref.column("b")), [2.0, 4.0])
        with self.assertRaises(HarnessError) as cm:
            ref.column("c")
        self.assertIn("no column 'c'", str(cm.exception))
        with self.assertRaises(HarnessError):
            ref.header_value(r"missing = ([0-9.]+)")

    def test_missing_file_and_missing_provenance(self):
        with self.assertRaises(HarnessError):
            ReferenceFile(self.root, "absent.csv")
        with self.assertRaises(HarnessError) as cm:
            ReferenceFile(self.root, "noheader.csv")
        self.assertIn("provenance", str(cm.exception))



class Ladder(unittest.TestCase):
    def test_every_rung_stands_on_exactly_one_step_of_the_ladder(self):
        from harness.casefile import discover
        from harness.ladder import load_ladder
        from support import ROOT
        named = [r for step in load_ladder() for r in step.rungs]
        rungs = [p.parent.name for p in discover(ROOT / "validation" / "cases")]
        self.assertEqual(sorted(named), sorted(rungs))

    def test_steps_not_built_name_the_issue_that_builds_them(self):
        from harness.ladder import load_ladder
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "ladder.toml"
            path.write_text('[[step]]\ntitle = "a later step"\nplanned = "issue 31"\n')
            self.assertEqual(load_ladder(path)[0].planned, "issue 31")
            for wrong in ('planned = "later"', 'planned = "issue 31"\nrungs = ["mms"]'):
                path.write_text(f'[[step]]\ntitle = "a later step"\n{wrong}\n')
                with self.assertRaisesRegex(HarnessError, "step\\[0\\]"):
                    load_ladder(path)


if __name__ == "__main__":
    unittest.main()
