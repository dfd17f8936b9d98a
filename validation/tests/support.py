import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "validation"))
NARWHAL = Path(os.environ.get("NARWHAL", ROOT / "build" / "solver" / "narwhal"))


def rung_in_temp_dir(rung_text, input_text=""):
    """(a new temporary folder, the rung loaded from it): case.toml from `rung_text` and its
    input in.toml beside it, under <folder>/rung."""
    import tempfile
    import textwrap
    from harness.casefile import load_rung
    folder = Path(tempfile.mkdtemp())
    case = folder / "rung"
    case.mkdir()
    (case / "in.toml").write_text(textwrap.dedent(input_text))
    (case / "case.toml").write_text(textwrap.dedent(rung_text))
    return folder, load_rung(case / "case.toml")
