#!/usr/bin/python3
"""Keeps a long report's finished runs in the repository (harness/archive.py says why and how).

  validation/tools/run_archive.py unpack --run-id n18   # before: validation/run ... --run-id n18 --resume
  validation/tools/run_archive.py pack --run-id n18     # after: then commit reports/archive/n18

The archive of report <run-id> is reports/archive/<run-id>/<rung>/<run>.tar.xz.
"""
import argparse
import json
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
sys.path.insert(0, str(ROOT / "validation"))

from harness.archive import pack, unpack  # noqa: E402
from harness.captive import ended_unsteady  # noqa: E402
from harness.casefile import discover, load_rung  # noqa: E402
from harness.errors import HarnessError  # noqa: E402


def restart_keeper(cases):
    """keeps_restart(rung, run_dir) for pack: whether another run of the rung starts from the run
    in run_dir: always, or for a sweep point's continuation (Run.when_unsteady) when the point's
    run.json says it ended unsteady."""
    always, when_unsteady = {}, {}
    for path in discover(cases):
        rung = load_rung(path)
        always[rung.name] = {r.restart_from for r in rung.runs if r.restart_from and not r.when_unsteady}
        when_unsteady[rung.name] = {r.restart_from: r.when_unsteady for r in rung.runs if r.when_unsteady}

    def keeps_restart(rung, run_dir):
        run = run_dir.name
        if run in always.get(rung, set()):
            return True
        if run not in when_unsteady.get(rung, {}):
            return False
        data = json.loads((run_dir / "run.json").read_text())
        return ended_unsteady(data, when_unsteady[rung][run], run)
    return keeps_restart


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("action", choices=("pack", "unpack"))
    ap.add_argument("--run-id", required=True, help="the report whose runs are archived or restored")
    ap.add_argument("--reports", default=str(ROOT / "reports"), help="where reports are written")
    ap.add_argument("--archive", default=None, help="default: <reports>/archive/<run-id>")
    ap.add_argument("--cases", default=str(ROOT / "validation" / "cases"), help="folder of rungs")
    args = ap.parse_args()
    report = Path(args.reports) / args.run_id
    archive = Path(args.archive) if args.archive else Path(args.reports) / "archive" / args.run_id
    try:
        if args.action == "pack":
            done = pack(report, archive, restart_keeper(args.cases))
        else:
            done = unpack(archive, report)
    except HarnessError as e:
        print(f"run_archive: {e}", file=sys.stderr)
        return 2
    print(f"run_archive: {args.action}ed {len(done)} run(s)")
    for p in done:
        print(f"  {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
