"""Benchmark history and regression flags.

Each benchmark run (Google Benchmark JSON with repetitions) is stored as one file in
benchmarks/history/ with machine, compiler and git SHA. A benchmark is flagged when
its median time exceeds the rolling median of the previous runs (same machine) by
more than the threshold (15 % by default, chosen above the run-to-run noise measured
by the repetitions' spread)."""
import datetime
import json
import statistics
from pathlib import Path

from .errors import HarnessError


def medians(gbench_json):
    """{benchmark name: median real time in ns} from Google Benchmark JSON output."""
    out = {}
    for b in gbench_json.get("benchmarks", []):
        if b.get("aggregate_name") == "median" or (b.get("run_type") == "iteration" and "aggregate_name" not in b):
            name = b.get("run_name", b["name"]).replace("_median", "")
            unit = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}[b.get("time_unit", "ns")]
            if b.get("aggregate_name") == "median" or name not in out:
                out[name] = b["real_time"] * unit
    if not out:
        raise HarnessError("no benchmark results in the Google Benchmark JSON")
    return out


def noise(gbench_json):
    """{benchmark name: coefficient of variation of the repetitions} where reported."""
    cv = {}
    for b in gbench_json.get("benchmarks", []):
        if b.get("aggregate_name") == "cv":
            cv[b.get("run_name", b["name"])] = b["real_time"]
    return cv


def append(history_dir, gbench_json, machine, compiler, git_sha, when=None):
    history_dir = Path(history_dir)
    history_dir.mkdir(parents=True, exist_ok=True)
    when = when or datetime.datetime.now(datetime.timezone.utc).strftime("%Y%m%dT%H%M%SZ")
    entry = {"when": when, "machine": machine, "compiler": compiler, "git_sha": git_sha,
             "median_ns": medians(gbench_json), "cv": noise(gbench_json)}
    path = history_dir / f"{when}-{git_sha}.json"
    path.write_text(json.dumps(entry, indent=1))
    return path


def load(history_dir):
    entries = []
    for p in sorted(Path(history_dir).glob("*.json")):
        entries.append(json.loads(p.read_text()))
    return sorted(entries, key=lambda e: e["when"])


def regressions(entries, threshold=0.15, window=5):
    """For the newest entry: per benchmark, (median now, rolling median before, ratio, verdict)
    with verdict "REGRESSION", "noisy" or "ok". Only earlier entries from the same machine count."""
    if not entries:
        return {}
    now = entries[-1]
    before = [e for e in entries[:-1] if e["machine"] == now["machine"]][-window:]
    out = {}
    for name, t in now["median_ns"].items():
        past = [e["median_ns"][name] for e in before if name in e["median_ns"]]
        if not past:
            out[name] = (t, None, None, "ok")
            continue
        ref = statistics.median(past)
        ratio = t / ref
        noise = 3.0 * now.get("cv", {}).get(name, 0.0)
        if ratio <= 1.0 + threshold:
            verdict = "ok"
        elif ratio <= 1.0 + noise:
            verdict = "noisy"
        else:
            verdict = "REGRESSION"
        out[name] = (t, ref, ratio, verdict)
    return out
