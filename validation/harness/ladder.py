"""The paper's validation ladder (validation/ladder.toml): its steps in order, the rungs
that test each, and the issue that builds a step not built yet."""
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

from .errors import HarnessError

LADDER = Path(__file__).resolve().parents[1] / "ladder.toml"


@dataclass
class Step:
    title: str
    rungs: tuple
    planned: str  # '' when built


def load_ladder(path=LADDER):
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        raise HarnessError(f"{path}: {e}")
    unknown = set(data) - {"step"}
    if unknown:
        raise HarnessError(f"{path}: unknown key(s) {', '.join(sorted(unknown))}")
    steps = []
    for i, t in enumerate(data.get("step", [])):
        bad = set(t) - {"title", "rungs", "planned"}
        if bad:
            raise HarnessError(f"{path}: key 'step[{i}]': unknown key(s) {', '.join(sorted(bad))}")
        if not isinstance(t.get("title"), str):
            raise HarnessError(f"{path}: key 'step[{i}].title': a title is required")
        rungs, planned = tuple(t.get("rungs", ())), t.get("planned", "")
        if bool(rungs) == bool(planned):
            raise HarnessError(f"{path}: key 'step[{i}]': give either rungs (built) or planned (not built yet)")
        if planned and not re.fullmatch(r"issue \d+", planned):
            raise HarnessError(f"{path}: key 'step[{i}].planned': expected the issue that builds the step, "
                               f"\"issue <number>\", got {planned!r}")
        steps.append(Step(t["title"], rungs, planned))
    return steps
