"""The run archive: finished runs of a long report kept in the repository, so that a nightly
report built up over several sittings survives machines that start empty.

A resumed report (runner.run_rung with resume) reuses a run whose folder holds the record of a
finished run of the same key (runner.RUN_RECORD). `pack` copies such runs into the archive, one
xz tarball per run, without the fields that only a continuation or a picture of the whole flow
would read (restart.h5, solution.cgns); `unpack` puts them back into a report's folder, where
the resumed report finds them as if they had been run there. A run's restart.h5 is kept when a
run of its rung starts from it (restart_from): that run may not have finished yet. A sweep point
whose continuation in physical time is made only when the point ended unsteady
(Run.when_unsteady) keeps it only then: most points settle, and their restarts would fill the
repository for nothing.
"""
import json
import tarfile
from pathlib import Path

from .errors import HarnessError
from .runner import RUN_RECORD, RUN_STARTED

RESTART = "restart.h5"
LEFT_OUT = {RESTART, "solution.cgns", ".narwhal.lock", RUN_STARTED}
SUFFIX = ".tar.xz"


def _recorded_key(run_dir):
    """The key of the finished run recorded in run_dir, or None."""
    try:
        return json.loads((run_dir / RUN_RECORD).read_text())["key"]
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _archived_key(tarball):
    try:
        with tarfile.open(tarball, "r:xz") as tar:
            return json.load(tar.extractfile(RUN_RECORD))["key"]
    except (OSError, tarfile.TarError, KeyError, ValueError, TypeError):
        return None


def pack(report_dir, archive_dir, keeps_restart=lambda rung, run_dir: False):
    """Archives every finished, recorded run under report_dir/<rung>/runs/<run>/ that the archive
    does not already hold under the same key. keeps_restart(rung, run_dir) tells whether another
    run of the rung starts from the run (its restart.h5 is kept). Returns the archived paths."""
    report_dir, archive_dir = Path(report_dir), Path(archive_dir)
    written = []
    for run_dir in sorted(report_dir.glob(f"*/runs/*/{RUN_RECORD}")):
        run_dir = run_dir.parent
        rung, run = run_dir.parent.parent.name, run_dir.name
        key = _recorded_key(run_dir)
        if key is None:
            continue
        target = archive_dir / rung / (run + SUFFIX)
        if target.exists() and _archived_key(target) == key:
            continue
        keep_restart = keeps_restart(rung, run_dir)
        if keep_restart and not (run_dir / RESTART).is_file():
            raise HarnessError(f"{run_dir}: run '{run}' is restarted from by another run of rung '{rung}', "
                               f"but its {RESTART} is missing")
        target.parent.mkdir(parents=True, exist_ok=True)
        partial = target.with_name(target.name + ".partial")
        with tarfile.open(partial, "w:xz") as tar:
            for f in sorted(run_dir.iterdir()):
                if f.is_file() and (f.name not in LEFT_OUT or (keep_restart and f.name == RESTART)):
                    tar.add(f, arcname=f.name)
        partial.replace(target)  # a half-written tarball is never taken for a run
        written.append(target)
    return written


def unpack(archive_dir, report_dir):
    """Puts each archived run into report_dir/<rung>/runs/<run>/ unless that folder already holds
    a finished run (a later sitting's, which wins). Returns the run folders written."""
    archive_dir, report_dir = Path(archive_dir), Path(report_dir)
    written = []
    for tarball in sorted(archive_dir.glob(f"*/*{SUFFIX}")):
        rung, run = tarball.parent.name, tarball.name[:-len(SUFFIX)]
        run_dir = report_dir / rung / "runs" / run
        if (run_dir / RUN_RECORD).exists():
            continue
        run_dir.mkdir(parents=True, exist_ok=True)
        try:
            with tarfile.open(tarball, "r:xz") as tar:
                members = tar.getmembers()
                bad = [m.name for m in members if not m.isfile() or "/" in m.name or m.name in ("", ".", "..")]
                if bad:
                    raise HarnessError(f"{tarball}: expected plain files only, found {bad}")
                for m in members:
                    # The record last: a folder interrupted mid-way is not taken for a finished run.
                    if m.name != RUN_RECORD:
                        (run_dir / m.name).write_bytes(tar.extractfile(m).read())
                (run_dir / RUN_RECORD).write_bytes(tar.extractfile(RUN_RECORD).read())
        except (tarfile.TarError, KeyError) as e:
            raise HarnessError(f"{tarball}: not a run archive ({e})")
        written.append(run_dir)
    return written
