import os
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "validation"))
NARWHAL = Path(os.environ.get("NARWHAL", ROOT / "build" / "solver" / "narwhal"))
