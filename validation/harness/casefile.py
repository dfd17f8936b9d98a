"""Rung definitions (validation/cases/<rung>/case.toml), read strictly.

A rung declares the solver runs it needs (optionally grouped in grid families, or
declared as a sweep of one case key), the tiers they belong to, and its checks. Unknown keys, wrong types and missing keys are
errors naming the file and the dotted key.
"""
import difflib
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from .errors import HarnessError
from . import extract as _extractors  # noqa: F401  (registers every extractor with its keys)
from .schema import OPTIONS, check_extract, check_options, check_reference, unknown_keys

TIERS = ("quick", "nightly")
COMPARATORS = tuple(OPTIONS)  # one list: the comparators and the options each takes (schema.py)


@dataclass
class Run:
    id: str
    input: Path
    tiers: tuple
    set: dict            # "dotted.key" -> TOML literal (string), passed as narwhal --set
    family: str = ""     # grid family name, '' for single runs
    h: float = 0.0       # representative spacing within the family, or "cells" (_grid_spacing)
    max_iterations: int = 0   # 0: the input's own limit
    restart_from: str = ""    # id of a run whose restart.h5 this run continues (a peer run: whose
                              # solution.cgns on the same grid it starts from)
    ranks: int = 0            # MPI ranks (mpirun); 0: validation/run --ranks (default 1)
    code: str = "narwhal"     # or a peer code on the same case and grid (PEER_CODES)
    model: str = ""           # a [[model]]'s id: `narwhal simulate` flies the case with it (after the
                              # rung's other runs, whose results the model is assembled from)
    when_unsteady: float = 0.0  # > 0: made only when the run it continues (restart_from) ended with
                                # its forces unsteady, run.json force_span above this (Unsteady)


@dataclass
class Unsteady:
    """How a sweep finishes a point whose steady iteration ends with its forces still
    swinging (a fin stalled on its lee side sheds, and no steady state exists): the point
    goes on in physical time from where its iteration ended, and its values are the means
    over the whole periods of the swing (harness/periodic.py). One rule for every point of
    the sweep, decided by the steady run's own result, so that no point is tuned by hand."""
    force_span: float    # a point goes on when its run.json force_span is above this
    discard: float       # physical time (L / U) from the continuation's start left out of the mean
    set: dict            # the dual-time settings laid over the point's own ("time.step" ...)
    run_ids: tuple       # the continuations' ids, "<point's run id>_time", as Sweep.run_ids


@dataclass
class Sweep:
    """Captive runs that differ in one case key (a drift angle, an angle of attack, a
    control deflection): one run per value, ids "<id>_<value>" (sweep_run_id)."""
    id: str
    variable: str        # the dotted case key swept, passed as narwhal --set
    values: tuple
    run_ids: tuple
    unsteady: Unsteady = None  # how a point whose forces do not settle is finished; None: it is not


@dataclass
class Model:
    """A manoeuvring model assembled from the rung's runs (solver/manoeuvring/DESIGN.md):
    each coefficient ([coefficients], ManoeuvringCoefficients' names; absent ones are 0) and
    each [propulsion] value (rps, wake_fraction, thrust_deduction) is an extractor's result,
    written to the model file `narwhal simulate` reads (which names a misspelled key)."""
    id: str
    coefficients: dict   # name -> extractor spec
    propulsion: dict     # name -> extractor spec


@dataclass
class Check:
    name: str
    tiers: tuple
    extract: dict
    reference: dict
    comparator: str
    tolerance: float
    rationale: str
    options: dict = field(default_factory=dict)


# Peer codes a run may be made with, on the run's own case file and Narwhal's grid of it
# (harness/openfoam.py); max_iterations is then the peer's iteration count.
PEER_CODES = ("openfoam",)

# Pictures of a run's surface output: "surface" (the body coloured by a column, in 3-D),
# "axial" (a column's azimuthal mean along x, with reference points if given) and
# "azimuthal" (the column around the body at the stations `stations`, x / L) and
# "friction_lines" (skin-friction lines on the unrolled body and the cross-flow
# separation line). `beside`: a second run of the rung (a peer code's) drawn on the same axes.
# "time_history": a dual-time run's column against time, `column` = "steps:<column of
# steps.csv>" or "motion:<column of motion.csv>", or motion:vertical_velocity (up positive) and
# motion:horizontal_speed (a free body's velocity against and across gravity) and
# motion:axis_from_vertical (the angle of its x axis from gravity, degrees); reference
# values without x are drawn as horizontal lines.
# "wake_strip": the flow speed in the plane y = y_O through a free body's origin, from
# the solution.cgns of `run` and of the runs in `then` (later states of the same fall,
# each continuing the one before), side by side.
# "side_view": a free body's path through the water in the vertical plane (travel against
# the stream, rise against gravity) with its axis drawn along it, nose marked; `beside`:
# the same manoeuvre at another time step or on another grid, on the same axes;
# "plan_view" the same seen from above (travel, to starboard). A time_history also draws
# motion:rise and motion:travel, controls:<column of controls.csv>, and
# propulsor:<column of propulsor.csv> (rps, thrust, torque, advance_ratio) at the end of each step.
PICTURE_KINDS = ("surface", "axial", "azimuthal", "friction_lines", "time_history", "wake_strip", "side_view",
                 "plan_view")
TIME_HISTORY_FILES = ("steps", "motion", "controls", "propulsor")


@dataclass
class Picture:
    kind: str
    run: str
    title: str
    tiers: tuple
    column: str = "cp"
    group: str = "body"
    reference: dict = field(default_factory=dict)
    beside: str = ""
    stations: list = field(default_factory=list)
    then: list = field(default_factory=list)


@dataclass
class Reported:
    """A quantity the rung reports without a reference or a tolerance (no pass or fail):
    a result the data set has nothing to compare with, such as a resistance at a speed
    the towing tank's table does not list."""
    name: str
    tiers: tuple
    extract: dict
    unit: str = ""


@dataclass
class Rung:
    name: str
    title: str
    directory: Path
    tiers: tuple
    timeout_s: float
    runs: list
    checks: list
    pictures: list
    reported: list = field(default_factory=list)
    sweeps: list = field(default_factory=list)
    models: list = field(default_factory=list)


class _Reader:
    """Looks keys up in a TOML table and remembers which were used."""

    def __init__(self, path, table, prefix=""):
        self.path, self.table, self.prefix, self.used = path, table, prefix, set()

    def _key(self, k):
        return f"{self.prefix}{k}"

    def get(self, key, kind, what, default=None, required=False):
        self.used.add(key)
        if key not in self.table:
            if required:
                raise HarnessError(f"{self.path}: key '{self._key(key)}': missing required key (expected {what})")
            return default
        v = self.table[key]
        ok = isinstance(v, kind) and not (kind in (int, float) and isinstance(v, bool))
        if kind is float and isinstance(v, int) and not isinstance(v, bool):
            v, ok = float(v), True
        if not ok:
            raise HarnessError(f"{self.path}: key '{self._key(key)}': expected {what}, got {type(v).__name__} {v!r}")
        return v

    def finish(self):
        unknown = [k for k in self.table if k not in self.used]
        if unknown:
            msgs = []
            for k in unknown:
                close = difflib.get_close_matches(k, sorted(self.used), n=1)
                hint = f" (did you mean '{self._key(close[0])}'?)" if close else ""
                msgs.append(f"unknown key '{self._key(k)}'{hint}")
            raise HarnessError(f"{self.path}: " + "; ".join(msgs))


def _grid_spacing(r):
    """A run's representative grid spacing h: a number, or "cells" for N^(-1/3) of the cell
    count its run.json reports (grid families generated member by member, whose
    refinement ratios are not exact)."""
    h = r.table.get("h", 0.0)
    r.used.add("h")
    if h == "cells":
        return h
    if isinstance(h, bool) or not isinstance(h, (int, float)):
        raise HarnessError(f"{r.path}: key '{r._key('h')}': expected the representative grid spacing (a number) "
                           f"or \"cells\", got {type(h).__name__} {h!r}")
    return float(h)


def _tiers(r, key, default, what):
    t = r.get(key, list, what, default=list(default))
    for x in t:
        if x not in TIERS:
            raise HarnessError(f"{r.path}: key '{r._key(key)}': unknown tier {x!r}; valid: {', '.join(TIERS)}")
    return tuple(t)


def _literal(v):
    """A Python value from tomllib back to TOML syntax for narwhal --set."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace('\\', '\\\\').replace('"', '\\"') + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_literal(x) for x in v) + "]"
    if isinstance(v, dict):  # an inline table: [[motion.ballast]] entries set as a list of them
        return "{" + ", ".join(f"{k} = {_literal(x)}" for k, x in v.items()) + "}"
    raise HarnessError(f"cannot pass {v!r} to narwhal --set")


def sweep_run_id(sweep_id, value):
    """The id of a sweep's run at `value`: -4 -> "<id>_m4", 2.5 -> "<id>_2p5"."""
    text = f"{float(value):g}".replace("-", "m").replace(".", "p").replace("+", "")
    return f"{sweep_id}_{text}"


def _input_and_overrides(r, path, table):
    """A run's or a sweep's solver input (which must exist) and its `set` overrides as --set literals."""
    inp = path.parent / r.get("input", str, "the solver input file (relative to the rung)", required=True)
    if not inp.exists():
        raise HarnessError(f"{path}: key '{table}.input': solver input '{inp}' does not exist")
    return inp, {k: _literal(v) for k, v in r.get("set", dict, "a table of overrides", default={}).items()}


def _read_sweeps(top, path, tiers):
    """The [[sweep]] tables and the runs they expand into. A sweep with `like = "<id>"`
    repeats an earlier sweep (its input, variable, overrides, tiers, ranks, iteration
    limit, the run it continues) with its own values and the overrides it adds: the same
    captive setup on another grid is one line, not a copy."""
    sweeps, runs, setups = [], [], {}
    for i, t in enumerate(top.get("sweep", list, "an array of [[sweep]] tables", default=[])):
        r = _Reader(path, t, f"sweep[{i}].")
        sid = r.get("id", str, "a sweep id", required=True)
        if sid in setups:
            raise HarnessError(f"{path}: key 'sweep[{i}].id': sweep ids must be unique; {sid!r} repeats")
        like = r.get("like", str, "the id of an earlier sweep this one repeats", default="")
        if like and like not in setups:
            raise HarnessError(f"{path}: key 'sweep[{i}].like': expected the id of an earlier sweep "
                               f"({', '.join(setups) or 'none'}), got {like!r}")
        base = setups.get(like, {"input": None, "variable": None, "set": {}, "tiers": tuple(tiers),
                                 "max_iterations": 0, "ranks": 0, "restart_from": "", "unsteady": None})
        if like and "input" not in t:
            inp, sets = base["input"], {**base["set"]}
            sets.update({k: _literal(v) for k, v in r.get("set", dict, "a table of overrides", default={}).items()})
        else:
            inp, own = _input_and_overrides(r, path, f"sweep[{i}]")
            sets = {**base["set"], **own}
        variable = r.get("variable", str, "the dotted case key swept, e.g. \"flow.drift_angle\"",
                         default=base["variable"], required=not like)
        if "." not in variable:
            raise HarnessError(f"{path}: key 'sweep[{i}].variable': expected a dotted case key such as "
                               f"\"flow.drift_angle\", got {variable!r}")
        values = r.get("values", list, "a list of the swept variable's values", required=True)
        if not values or not all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
            raise HarnessError(f"{path}: key 'sweep[{i}].values': expected a non-empty list of numbers, got {values!r}")
        values = tuple(float(v) for v in values)
        if len(set(values)) != len(values):
            raise HarnessError(f"{path}: key 'sweep[{i}].values': values repeat: {list(values)}")
        if variable in sets:
            raise HarnessError(f"{path}: key 'sweep[{i}].set': sets the swept variable '{variable}'")
        setup = {"input": inp, "variable": variable, "set": sets,
                 "tiers": _tiers(r, "tiers", base["tiers"], "a list of tiers"),
                 "max_iterations": r.get("max_iterations", int, "an iteration limit", default=base["max_iterations"]),
                 "ranks": r.get("ranks", int, "a number of MPI ranks", default=base["ranks"]),
                 "restart_from": r.get("restart_from", str, "the id of the run every point continues",
                                       default=base["restart_from"]),
                 "unsteady": _read_unsteady(r, path, f"sweep[{i}]", base["unsteady"])}
        r.finish()
        setups[sid] = setup
        ids = tuple(sweep_run_id(sid, v) for v in values)
        unsteady = setup["unsteady"]
        if unsteady:
            unsteady = Unsteady(**unsteady, run_ids=tuple(f"{rid}_time" for rid in ids))
        sweeps.append(Sweep(id=sid, variable=variable, values=values, run_ids=ids, unsteady=unsteady))
        for rid, v in zip(ids, values):
            point_set = {**sets, variable: _literal(v)}
            runs.append(Run(id=rid, input=inp, tiers=setup["tiers"], set=point_set,
                            max_iterations=setup["max_iterations"], ranks=setup["ranks"],
                            restart_from=setup["restart_from"]))
            if unsteady:
                runs.append(Run(id=f"{rid}_time", input=inp, tiers=setup["tiers"],
                                set={**point_set, **unsteady.set}, ranks=setup["ranks"], restart_from=rid,
                                when_unsteady=unsteady.force_span))
    return sweeps, runs


def _read_unsteady(sweep_reader, path, where, inherited):
    """A sweep's [sweep.unsteady] table (Unsteady) as a dict without its run ids, or the one
    the sweep it repeats (`like`) has. The table may be a TOML file's, named relative to the
    case file, so that several rungs share one rule."""
    if isinstance(sweep_reader.table.get("unsteady"), str):
        name = sweep_reader.get("unsteady", str, "a file holding the table")
        source = (path.parent / name).resolve()
        try:
            table = tomllib.loads(source.read_text())
        except (OSError, tomllib.TOMLDecodeError) as e:
            raise HarnessError(f"{path}: key '{where}.unsteady': cannot read {source}: {e}") from e
        path, prefix = source, ""
    else:
        prefix = f"{where}.unsteady."
        table = sweep_reader.get("unsteady", dict, "a table (force_span, discard, set) or a file holding one",
                                 default=None)
    if table is None:
        return inherited
    r = _Reader(path, table, prefix)
    force_span = r.get("force_span", float, "the force span above which a point goes on in physical time",
                       required=True)
    discard = r.get("discard", float, "the physical time (L / U) left out of the mean as the start's transient",
                    required=True)
    sets = {k: _literal(v) for k, v in r.get("set", dict, "a table of dual-time overrides (\"time.step\" ...)",
                                             required=True).items()}
    r.finish()
    if force_span <= 0.0 or discard < 0.0:
        raise HarnessError(f"{path}: keys '{prefix}force_span', '{prefix}discard': expected force_span > 0 and "
                           f"discard >= 0, got {force_span!r} and {discard!r}")
    if not any(k.startswith("time.") for k in sets):
        raise HarnessError(f"{path}: key '{prefix}set': expected the dual-time settings (time.scheme, "
                           f"time.step, time.steps ...), got {sorted(sets)}")
    return {"force_span": force_span, "discard": discard, "set": sets}


def load_rung(path):
    path = Path(path)
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except FileNotFoundError:
        raise HarnessError(f"{path}: rung file does not exist")
    except tomllib.TOMLDecodeError as e:
        raise HarnessError(f"{path}: TOML syntax error: {e}")
    top = _Reader(path, data)
    meta = _Reader(path, top.get("rung", dict, "a [rung] table", required=True), "rung.")
    title = meta.get("title", str, "a one-line title", required=True)
    tiers = _tiers(meta, "tiers", (), "a list of tiers")
    if not tiers:
        raise HarnessError(f"{path}: key 'rung.tiers': at least one tier is required")
    timeout = meta.get("timeout_s", float, "a time limit in seconds", default=1800.0)
    meta.finish()

    runs = _read_runs(top, path, tiers)
    sweeps, sweep_runs = _read_sweeps(top, path, tiers)
    runs += sweep_runs
    ids = [x.id for x in runs]
    if len(set(ids)) != len(ids):
        raise HarnessError(f"{path}: run ids must be unique (a sweep's are <sweep id>_<value>), got {ids}")
    if len({x.id for x in sweeps}) != len(sweeps):
        raise HarnessError(f"{path}: sweep ids must be unique, got {[x.id for x in sweeps]}")
    models = _read_models(top, path)
    _check_run_links(runs, models, path)
    checks = _read_checks(top, path, tiers)
    reported = _read_reported(top, path, tiers)
    pictures = _read_pictures(top, path, tiers, ids)
    top.finish()
    return Rung(name=path.parent.name, title=title, directory=path.parent, tiers=tiers, timeout_s=timeout,
                runs=runs, checks=checks, pictures=pictures, reported=reported, sweeps=sweeps, models=models)


def _read_runs(top, path, tiers):
    """The [[run]] tables (a sweep's runs come from _read_sweeps)."""
    runs = []
    for i, t in enumerate(top.get("run", list, "an array of [[run]] tables", default=[])):
        r = _Reader(path, t, f"run[{i}].")
        rid = r.get("id", str, "a run id", required=True)
        inp, sets = _input_and_overrides(r, path, f"run[{i}]")
        runs.append(Run(id=rid, input=inp, tiers=_tiers(r, "tiers", tiers, "a list of tiers"), set=sets,
                        family=r.get("family", str, "a grid-family name", default=""),
                        h=_grid_spacing(r),
                        max_iterations=r.get("max_iterations", int, "an iteration limit", default=0),
                        restart_from=r.get("restart_from", str, "the id of the run to continue", default=""),
                        ranks=r.get("ranks", int, "a number of MPI ranks", default=0),
                        code=r.get("code", str, "narwhal or a peer code (" + ", ".join(PEER_CODES) + ")",
                                   default="narwhal"),
                        model=r.get("model", str, "the id of a [[model]] to fly the case with", default="")))
        if runs[-1].code not in ("narwhal",) + PEER_CODES:
            raise HarnessError(f"{path}: key 'run[{i}].code': unknown code {runs[-1].code!r}; valid: narwhal, "
                               + ", ".join(PEER_CODES))
        if runs[-1].model and (runs[-1].code != "narwhal" or runs[-1].restart_from or runs[-1].ranks
                               or runs[-1].max_iterations or runs[-1].family):
            raise HarnessError(f"{path}: run '{rid}': a run flown by a model (model = ...) takes no code, "
                               "restart_from, ranks, max_iterations or family")
        if runs[-1].code != "narwhal" and runs[-1].max_iterations <= 0:
            raise HarnessError(f"{path}: run '{rid}': a peer run needs max_iterations (its iteration count)")
        r.finish()
    return runs


def _check_run_links(runs, models, path):
    """What a run names (its model, the run it restarts from, its family's h) must exist and fit."""
    ids = [x.id for x in runs]
    for x in runs:
        if x.model and x.model not in [m.id for m in models]:
            raise HarnessError(f"{path}: run '{x.id}': model names unknown [[model]] '{x.model}'; models: "
                               + (", ".join(m.id for m in models) or "none"))
        if x.restart_from and x.restart_from in ids and runs[ids.index(x.restart_from)].model:
            raise HarnessError(f"{path}: run '{x.id}': restart_from names '{x.restart_from}', a run flown by a model")
        if x.family and x.h != "cells" and x.h <= 0.0:
            raise HarnessError(f"{path}: run '{x.id}' is in family '{x.family}' but has no positive 'h'")
        if x.restart_from and x.restart_from not in ids:
            raise HarnessError(f"{path}: run '{x.id}': restart_from names unknown run '{x.restart_from}'")
        if x.restart_from and runs[ids.index(x.restart_from)].code != "narwhal":
            raise HarnessError(f"{path}: run '{x.id}': restart_from names '{x.restart_from}', a peer run; "
                               "runs start only from a Narwhal run")


def _read_checks(top, path, tiers):
    """The [[check]] tables: an extractor, a reference, a closed comparator, a tolerance and its reason."""
    checks = []
    for i, t in enumerate(top.get("check", list, "an array of [[check]] tables", default=[])):
        r = _Reader(path, t, f"check[{i}].")
        comp = r.get("comparator", str, "a comparator", required=True)
        if comp not in COMPARATORS:
            raise HarnessError(f"{path}: key 'check[{i}].comparator': unknown comparator {comp!r}; "
                               f"valid: {', '.join(COMPARATORS)}")
        c = Check(name=r.get("name", str, "a check name", required=True),
                  tiers=_tiers(r, "tiers", tiers, "a list of tiers"),
                  extract=r.get("extract", dict, "an extractor table", required=True),
                  reference=r.get("reference", dict, "a reference table", default={}),
                  comparator=comp,
                  tolerance=r.get("tolerance", float, "a numeric tolerance", required=True),
                  rationale=r.get("rationale", str, "a one-line reason for the tolerance", required=True),
                  options=r.get("options", dict, "a table of comparator options", default={}))
        try:
            check_extract(c.extract, f"check[{i}].extract")
            check_reference(c.reference, f"check[{i}].reference")
            check_options(comp, c.options, f"check[{i}].options")
        except HarnessError as e:
            raise HarnessError(f"{path}: {e}")
        if not c.rationale.strip():
            raise HarnessError(f"{path}: key 'check[{i}].rationale': must say why the tolerance is what it is")
        r.finish()
        checks.append(c)
    return checks


def _read_reported(top, path, tiers):
    """The [[report]] tables: quantities shown on the rung's page without a check."""
    reported = []
    for i, t in enumerate(top.get("report", list, "an array of [[report]] tables", default=[])):
        r = _Reader(path, t, f"report[{i}].")
        q = Reported(name=r.get("name", str, "a name", required=True),
                     tiers=_tiers(r, "tiers", tiers, "a list of tiers"),
                     extract=r.get("extract", dict, "an extractor table", required=True),
                     unit=r.get("unit", str, "the unit shown", default=""))
        try:
            check_extract(q.extract, f"report[{i}].extract")
        except HarnessError as e:
            raise HarnessError(f"{path}: {e}")
        r.finish()
        reported.append(q)
    return reported


def _read_pictures(top, path, tiers, ids):
    """The [[picture]] tables; the runs they draw must be the rung's."""
    pictures = []
    for i, t in enumerate(top.get("picture", list, "an array of [[picture]] tables", default=[])):
        r = _Reader(path, t, f"picture[{i}].")
        kind = r.get("kind", str, "a picture kind: " + " or ".join(PICTURE_KINDS), required=True)
        if kind not in PICTURE_KINDS:
            raise HarnessError(f"{path}: key 'picture[{i}].kind': unknown picture kind {kind!r}; "
                               f"valid: {', '.join(PICTURE_KINDS)}")
        pic = Picture(kind=kind, run=r.get("run", str, "the run whose surface is drawn", required=True),
                      title=r.get("title", str, "a title", required=True),
                      tiers=_tiers(r, "tiers", tiers, "a list of tiers"),
                      column=r.get("column", str, "the surface column drawn", default="cp"),
                      group=r.get("group", str, "the wall group", default="body"),
                      reference=r.get("reference", dict, "reference points {file, where, x, y, label}", default={}),
                      beside=r.get("beside", str, "the id of a run drawn beside it", default=""),
                      stations=r.get("stations", list, "a list of axial stations x / L", default=[]),
                      then=r.get("then", list, "a list of run ids (later states)", default=[]))
        for key, run in (("run", pic.run), ("beside", pic.beside), *(("then", x) for x in pic.then)):
            if run and run not in ids:
                raise HarnessError(f"{path}: key 'picture[{i}].{key}': unknown run '{run}'")
        if pic.then and kind != "wake_strip":
            raise HarnessError(f"{path}: key 'picture[{i}].then': only a wake_strip picture takes later runs")
        if (kind == "azimuthal") != bool(pic.stations) or \
                not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in pic.stations):
            raise HarnessError(f"{path}: key 'picture[{i}].stations': an azimuthal picture (and only it) takes a "
                               f"list of axial stations x / L; got {pic.stations!r}")
        if kind == "time_history" and pic.column.partition(":")[0] not in TIME_HISTORY_FILES:
            raise HarnessError(f"{path}: key 'picture[{i}].column': a time_history picture draws \"<file>:<column>\", "
                               f"<file> one of {', '.join(TIME_HISTORY_FILES)}; got {pic.column!r}")
        try:
            unknown_keys(pic.reference, ("file", "where", "x", "y", "label"), f"picture[{i}].reference")
        except HarnessError as e:
            raise HarnessError(f"{path}: {e}")
        r.finish()
        pictures.append(pic)
    return pictures


def _read_models(top, path):
    models = []
    for i, t in enumerate(top.get("model", list, "an array of [[model]] tables", default=[])):
        r = _Reader(path, t, f"model[{i}].")
        m = Model(id=r.get("id", str, "a model id", required=True),
                  coefficients=r.get("coefficients", dict, "a table: coefficient name -> extractor", required=True),
                  propulsion=r.get("propulsion", dict, "a table: rps, wake_fraction, thrust_deduction -> extractor",
                                   default={}))
        for table, specs in (("coefficients", m.coefficients), ("propulsion", m.propulsion)):
            for name, spec in specs.items():
                where = f"model[{i}].{table}.{name}"
                if not isinstance(spec, dict):
                    raise HarnessError(f"{path}: key '{where}': expected an extractor table {{kind = ...}} "
                                       f"(every value comes from the rung's runs), got {spec!r}")
                try:
                    check_extract(spec, where)
                except HarnessError as e:
                    raise HarnessError(f"{path}: {e}")
        r.finish()
        models.append(m)
    if len({m.id for m in models}) != len(models):
        raise HarnessError(f"{path}: model ids must be unique, got {[m.id for m in models]}")
    return models


def discover(cases_dir):
    return sorted(p for p in Path(cases_dir).glob("*/case.toml"))
