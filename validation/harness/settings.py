"""The solver settings a rung's Narwhal runs used (run.json's "settings": turbulence model,
scheme, CFL law, multigrid, convergence criteria), so that a rung can show, and check, that
one set of settings served every configuration and angle it ran (no per-point tuning)."""
import json

from .errors import HarnessError
from .schema import extractor


def run_settings(run_dir):
    """run.json's settings table of one run, or None when it has none (a peer code's run, or
    a run that stopped before writing run.json)."""
    try:
        with open(run_dir / "run.json") as f:
            return json.load(f).get("settings")
    except (OSError, ValueError):
        return None


def split_settings(by_run, ignore=()):
    """(shared, differing): the settings every run has with one value, and for each setting
    that is missing from a run or has more than one value, its value per run (None: missing)."""
    keys = sorted({k for s in by_run.values() for k in s} - set(ignore))
    shared, differing = {}, {}
    for k in keys:
        values = {rid: s.get(k) for rid, s in by_run.items()}
        distinct = {json.dumps(v, sort_keys=True) for v in values.values()}
        if len(distinct) == 1 and all(k in s for s in by_run.values()):
            shared[k] = next(iter(values.values()))
        else:
            differing[k] = values
    return shared, differing


def rung_settings(ctx):
    """{run id: settings} over the rung's Narwhal runs of this tier that wrote them."""
    out = {}
    for rid in ctx.run_dirs:
        if ctx.run_code(rid) != "narwhal":
            continue
        s = run_settings(ctx.run_dir(rid))
        if s is not None:
            out[rid] = s
    return out


@extractor("settings_differing", "ignore")
def settings_differing(ctx, spec, run_id):
    """How many solver settings differ between the rung's Narwhal runs (a setting a run lacks
    counts as differing); `ignore` names settings allowed to differ. Zero when one set of
    settings served every run; the report's settings table names any that differ."""
    ignore = spec.get("ignore", [])
    if not isinstance(ignore, list) or not all(isinstance(k, str) for k in ignore):
        raise HarnessError(f"extractor 'settings_differing': 'ignore' must be a list of setting names, got {ignore!r}")
    by_run = rung_settings(ctx)
    if len(by_run) < 2:
        raise HarnessError(f"rung '{ctx.rung.name}': settings_differing needs two or more Narwhal runs with "
                           f"settings in run.json, found {len(by_run)}")
    return float(len(split_settings(by_run, ignore)[1]))
