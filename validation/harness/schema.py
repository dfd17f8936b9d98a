"""The keys each extractor, reference and comparator accepts: one declaration per
kind, checked when a rung file is loaded (a misspelled key is an error before any
run starts) and enforced while extracting (an extractor that reads a key it has not
declared is a harness bug, reported as such)."""
import difflib

from .errors import HarnessError

# Keys every extraction may carry: which run (or grid family) it reads.
EXTRACT_COMMON = ("kind", "run", "family")

# kind -> (function, the keys it reads); filled by @extractor where each is defined.
EXTRACT = {}


def extractor(kind, *keys):
    """Registers an extractor under `kind` with the keys it reads (besides EXTRACT_COMMON)."""
    def register(fn):
        EXTRACT[kind] = (fn, keys)
        return fn
    return register


# Extractions whose values are extractions themselves.
NESTED = {"ratio": ("a", "b"), "difference": ("a", "b"), "curve_difference": ("a", "b"), "dimensional": ("of",)}

# `extract`: the reference is another run's value (a peer code's run), extracted as the
# computed value is; the other keys read a file under reference_data/.
# `minus`: the same column's value in the row it selects (as `where`) is subtracted (a
# measured increment between two configurations).
REFERENCE = ("file", "derive", "params", "header", "x", "y", "where", "column", "row", "minus", "extract")
DNS_REFERENCE = ("file", "where")

# Options a comparator takes; log_x (a logarithmic x axis in the report) goes with any.
OPTIONS_COMMON = ("log_x",)
OPTIONS = {
    "abs": (), "rel": (), "max": (), "min": (), "restart_equal": (),
    "profile_rms": ("relative",), "profile_max": ("relative",),
    "observed_order": ("pairs",), "gci": ("safety_factor",), "family_spread": (),
}


def unknown_keys(table, allowed, where):
    """HarnessError naming every key of `table` not in `allowed` (with the closest valid one)."""
    bad = [k for k in table if k not in allowed]
    if not bad:
        return
    msgs = []
    for k in bad:
        close = difflib.get_close_matches(k, allowed, n=1)
        hint = f" (did you mean '{where}.{close[0]}'?)" if close else f" (valid: {', '.join(allowed)})"
        msgs.append(f"unknown key '{where}.{k}'{hint}")
    raise HarnessError("; ".join(msgs))


def check_extract(spec, where):
    kind = spec.get("kind")
    if kind not in EXTRACT:
        raise HarnessError(f"key '{where}.kind': unknown extractor {kind!r}; valid: {', '.join(EXTRACT)}")
    unknown_keys(spec, EXTRACT_COMMON + EXTRACT[kind][1], where)
    for key in NESTED.get(kind, ()):
        if isinstance(spec.get(key), dict):
            check_extract(spec[key], f"{where}.{key}")
    if isinstance(spec.get("dns"), dict):
        unknown_keys(spec["dns"], DNS_REFERENCE, f"{where}.dns")


def check_reference(spec, where):
    unknown_keys(spec, REFERENCE, where)
    if isinstance(spec.get("extract"), dict):
        if len(spec) != 1:
            raise HarnessError(f"{where}: a reference taken from a run ('extract') takes no other key")
        check_extract(spec["extract"], f"{where}.extract")


def check_options(comparator, options, where):
    unknown_keys(options, OPTIONS_COMMON + OPTIONS[comparator], where)


class Declared(dict):
    """The extraction table as an extractor sees it: reading an undeclared key raises."""

    def __init__(self, spec):
        super().__init__(spec)
        self.allowed = EXTRACT_COMMON + EXTRACT.get(spec.get("kind"), (None, ()))[1]

    def _guard(self, key):
        if key not in self.allowed:
            raise HarnessError(f"harness bug: extractor '{self.get('kind')}' reads key '{key}', "
                               f"which harness/schema.py does not declare for it")

    def __getitem__(self, key):
        self._guard(key)
        return super().__getitem__(key)

    def get(self, key, default=None):
        self._guard(key)
        return super().get(key, default)

    def __contains__(self, key):
        self._guard(key)
        return super().__contains__(key)
