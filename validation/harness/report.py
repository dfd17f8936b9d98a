"""Static HTML report from results.json files: summary, one page per rung with plots
next to the reference data, and a performance page with history. Self-contained: no
network resources; every page marks <body data-images="ok|broken:N"> once loaded so a
headless browser can tell whether all images rendered."""
import html
import json
import shutil
import textwrap
from pathlib import Path

import matplotlib
import matplotlib.ticker

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from . import browser  # noqa: E402
from .body import (around, azimuthal_mean, meridian_stations, meridians, separation_azimuth,  # noqa: E402
                   with_crossflow_friction)
from .extract import read_csv  # noqa: E402
from .propulsor import propulsor_per_step  # noqa: E402
from .motion import axis_from_vertical_deg, body_axis, fall_components, gravity_direction, water_path  # noqa: E402
from .solution import read_solution  # noqa: E402
from .errors import HarnessError  # noqa: E402
from .settings import split_settings  # noqa: E402
from .ladder import load_ladder  # noqa: E402

ONE_SIDED = {"max": "≤", "min": "≥"}
# Checks judged against a bound: the summary shows the bound instead of a reference and a
# delta (a GCI is bounded above; its reference value, if any, is drawn in its figure).
BOUNDED = dict(ONE_SIDED, gci="≤")

CSS = """
body{font-family:system-ui,sans-serif;margin:2em;color:#222;max-width:1200px}
table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #ccc;padding:4px 8px;font-size:14px}
th{background:#f3f3f3}.PASS,.passed{color:#07702a;font-weight:bold}.FAIL,.failed,.crashed,.timeout{color:#b00020;font-weight:bold}.skipped,.notbuilt{color:#666;font-weight:bold}.notinthisrun{color:#666}
.num{font-family:ui-monospace,monospace;text-align:right}img{max-width:560px;border:1px solid #ddd;margin:4px}
.why{color:#555;font-size:13px}nav a{margin-right:1em}
"""
IMAGE_CHECK = """<script>
window.addEventListener('load', function () {
  var bad = 0, imgs = document.images;
  for (var i = 0; i < imgs.length; ++i) if (!imgs[i].complete || imgs[i].naturalWidth === 0) bad++;
  document.body.setAttribute('data-images', bad ? 'broken:' + bad : 'ok');
});
</script>"""


def _save(fig, path):
    """Every report figure: tight layout, 90 dpi PNG, figure closed."""
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def _page(title, body, depth=0):
    up = "../" * depth
    nav = f'<nav><a href="{up}index.html">Summary</a><a href="{up}perf.html">Performance</a></nav>'
    return (f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(title)}</title>"
            f"<style>{CSS}</style></head><body data-images='pending'>{nav}<h1>{html.escape(title)}</h1>{body}"
            f"{IMAGE_CHECK}</body></html>")


def _fmt(v):
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v:.6g}"
    return html.escape(str(v))


def _check_cells(c):
    """computed, reference, delta and tolerance cells of a check: a one-sided check shows
    its bound (<= or >= the tolerance) in place of a reference, and no delta."""
    bound = BOUNDED.get(c["comparator"])
    if bound:
        return (f"<td class=num>{_fmt(c.get('computed'))}</td><td class=num>{bound} {_fmt(c['tolerance'])}</td>"
                f"<td class=num>—</td><td class=num>(bound)</td>")
    return (f"<td class=num>{_fmt(c.get('computed'))}</td><td class=num>{_fmt(c.get('reference'))}</td>"
            f"<td class=num>{_fmt(c.get('delta'))}</td><td class=num>{_fmt(c['tolerance'])}</td>")


def _title(ax, text):
    """A check's name as a figure title, wrapped so that it is never cut."""
    ax.set_title("\n".join(textwrap.wrap(text, 70)), fontsize=9)


def _to_uniform(y, z, f, n=41):
    """A tensor-grid field f[z, y] interpolated (bilinearly) onto n x n uniform points."""
    yu, zu = np.linspace(y.min(), y.max(), n), np.linspace(z.min(), z.max(), n)
    along_y = np.array([np.interp(yu, y, row) for row in f])
    return yu, zu, np.array([np.interp(zu, z, col) for col in along_y.T]).T


def _plot_duct_field(check, p):
    """Isovels U/U_b and secondary-flow streamlines (line width ~ speed) of the run
    beside the DNS field."""
    panels = [("Narwhal", p["y"], p["z"], p["u"], p["v"], p["w"])]
    if p.get("dns"):
        d = p["dns"]
        panels.append(("DNS (reference)", d["y"], d["z"], d["u"], d["v"], d["w"]))
    fig = plt.figure(figsize=(5.6 * len(panels) + 0.8, 5.6))
    grid = fig.add_gridspec(1, len(panels) + 1, width_ratios=[1.0] * len(panels) + [0.05])
    levels = np.linspace(0.1, 1.4, 14)
    for n, (name, y, z, u, v, w) in enumerate(panels):
        ax = fig.add_subplot(grid[0, n])
        y, z = np.asarray(y, float), np.asarray(z, float)
        u, v, w = (np.asarray(a, float) for a in (u, v, w))
        cs = ax.contourf(y, z, u, levels=levels, cmap="viridis", extend="both")
        ax.contour(y, z, u, levels=levels, colors="k", linewidths=0.3)
        yu, zu, vu = _to_uniform(y, z, v)
        _, _, wu = _to_uniform(y, z, w)
        speed = np.hypot(vu, wu)
        ax.streamplot(yu, zu, vu, wu, color="white", density=1.4, arrowsize=0.7,
                      linewidth=0.3 + 1.5 * speed / max(speed.max(), 1e-30))
        ax.set_title(f"{name}: max |(V, W)| = {100 * np.nanmax(np.hypot(v, w)):.2f} % U_b", fontsize=10)
        ax.set_aspect("equal")
        ax.set_xlim(-1, 1)
        ax.set_ylim(-1, 1)
        ax.set_xlabel("y/h")
        ax.set_ylabel("z/h")
    fig.colorbar(cs, cax=fig.add_subplot(grid[0, -1]), label="U/U_b")
    fig.suptitle(f"{check['name']}\n{p['cells']} vortex cells in the secondary stream function", fontsize=10)


def _band(c, r):
    """(low, high) of the values a scalar check accepts around reference r."""
    t, comp = c["tolerance"], c["comparator"]
    if comp == "rel":
        return r * (1 - t), r * (1 + t)
    if comp in ("abs", "restart_equal"):
        return r - t, r + t
    if comp == "max":
        return -np.inf, t
    return t, np.inf


def _plot_scalar(check, path):
    """The computed value on a number line with the reference and the accepted band."""
    comp, c, r = check["comparator"], check.get("computed"), check.get("reference")
    if c is None or (r is None and comp not in ONE_SIDED):
        return False
    lo, hi = _band(check, r)
    finite = [v for v in (c, r, lo, hi) if v is not None and np.isfinite(v)]
    span = max(finite) - min(finite) or max(abs(max(finite)), 1e-30)
    x0, x1 = min(finite) - 0.3 * span, max(finite) + 0.3 * span
    fig, ax = plt.subplots(figsize=(6.4, 1.9))
    ax.axvspan(max(lo, x0), min(hi, x1), color="tab:green", alpha=0.15,
               label=f"accepted ({ONE_SIDED.get(comp, '±')} {check['tolerance']:g})")
    if r is not None and comp not in ONE_SIDED:
        ax.axvline(r, color="k", lw=1.5, label=f"reference {r:.6g}")
    ax.plot([c], [0.5], "o", color="tab:blue", ms=8, label=f"Narwhal {c:.6g}")
    ax.set_xlim(x0, x1)
    ax.xaxis.set_major_locator(matplotlib.ticker.MaxNLocator(5))
    ax.set_ylim(0, 1)
    ax.set_yticks([])
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.0, 1.0))
    _title(ax, check["name"])
    _save(fig, path)
    return True


def _plot_family(check, p, ax):
    h, v = np.array(p["h"]), np.array(p["values"])
    if check["comparator"] in ("gci", "family_spread"):
        # Values against h with the Richardson-extrapolated value at h = 0, the reference,
        # and the band the GCI puts around the finest grid's value.
        ax.plot(h, v, "o-", label="Narwhal")
        f_ext = p.get("extrapolated")
        if f_ext is not None:
            ax.plot([0.0], [f_ext], "s", color="tab:purple", label=f"extrapolated {f_ext:.6g}")
            ax.plot([0.0, h[-1]], [f_ext, v[-1]], ":", color="tab:purple", lw=1)
        ref = check.get("reference")
        if ref is not None:
            ax.axhline(ref, color="k", lw=1.5, label=f"reference {ref:.6g}")
        g = check["tolerance"] * abs(v[-1])
        bound = "GCI bound" if check["comparator"] == "gci" else "accepted spread"
        ax.axhspan(v[-1] - g, v[-1] + g, color="tab:green", alpha=0.12,
                   label=f"finest ± {bound} {100 * check['tolerance']:g} %")
        ax.set_xlim(left=0.0)
        ax.set_xlabel("grid spacing h")
        return
    av = np.abs(v)
    ax.loglog(h, av, "o-", label="Narwhal")
    theory = p.get("theory")
    if theory:
        ax.loglog(h, av[-1] * (h / h[-1]) ** theory, "k--", lw=1, label=f"reference: order {theory:g}")
        low = theory - check["tolerance"]
        ax.fill_between(h, av[-1] * (h / h[-1]) ** theory, av[-1] * (h / h[-1]) ** low, color="tab:green",
                        alpha=0.12, label=f"accepted: order ≥ {low:g}")
    for i, o in enumerate(p.get("orders", [])):
        ax.annotate(f"{o:.2f}", (np.sqrt(h[i] * h[i + 1]), np.sqrt(av[i] * av[i + 1])), fontsize=8)
    ax.set_xlabel("grid spacing h")


def _plot_check(check, path):
    p = check.get("plot")
    if not p:
        return _plot_scalar(check, path)
    if p["kind"] == "duct_field":
        _plot_duct_field(check, p)
        _save(plt.gcf(), path)
        return True
    if p["kind"] == "curve":
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(6.4, 5.6), sharex=True, gridspec_kw={"height_ratios": [2, 1]})
        x = np.array(p["x"])
        a1.plot(x, p["ref"], "k-", lw=1.5, label="reference")
        a1.plot(x, p["y"], "o", ms=3, color="tab:blue", label="Narwhal")
        a1.legend(fontsize=8)
        _title(a1, check["name"])
        a2.plot(x, 100 * np.array(p["err"]) if p["relative"] else p["err"], "-", color="tab:red", label="error")
        a2.axhline(0, color="k", lw=0.5)
        tol = check["tolerance"] * (100 if p["relative"] else 1)
        what = "max |error|" if check["comparator"] == "profile_max" else "RMS error"
        a2.axhspan(-tol, tol, color="tab:green", alpha=0.12, label=f"tolerance ({what})")
        a2.legend(fontsize=8)
        a2.set_ylabel("error [%]" if p["relative"] else "error")
        if check.get("options", {}).get("log_x"):  # e.g. u+(y+)
            a2.set_xscale("log")
    else:
        fig, ax = plt.subplots(figsize=(6.4, 4.6))
        _plot_family(check, p, ax)
        _title(ax, check["name"])
        ax.legend(fontsize=8)
    _save(fig, path)
    return True


def _surface_table(rung_dir, pic):
    path = rung_dir / "runs" / pic["run"] / f"surface_{pic['group']}.csv"
    if not path.exists():
        return None
    t = read_csv(path)
    return t if pic["column"] in t else None


def _picture_surface(t, pic, side, unrolled):
    """The body coloured by the column: seen from the side (the half at y <= 0, x to the
    right, z up, to scale) and unrolled (x against the azimuth from +z, every face)."""
    x, y, z, v = t["x"], t["y"], t["z"], t[pic["column"]]
    lo, hi = np.percentile(v, [1, 99])  # stagnation points would take the whole scale
    near = np.argsort(-y)  # the faces nearest the viewer (y most negative) drawn last
    near = near[y[near] <= 0.0]
    dot = float(np.clip(4e4 / x.size, 1.0, 12.0))  # coarse grids: bigger dots
    sc = side.scatter(x[near], z[near], c=v[near], s=dot, cmap="viridis", vmin=lo, vmax=hi)
    side.set_aspect("equal")
    side.set_xlabel("x")
    side.set_ylabel("z")
    phi = np.degrees(np.arctan2(-y, z))
    unrolled.scatter(x, phi, c=v, s=dot, cmap="viridis", vmin=lo, vmax=hi)
    unrolled.set_xlabel("x")
    unrolled.set_ylabel("azimuth from +z [deg]")
    return sc


def _picture_axial(t, pic, ax):
    """The column's azimuthal mean along x, with the reference points if any."""
    xs = meridian_stations(t)
    ax.plot(xs, azimuthal_mean(t, pic["column"], xs), "-", color="tab:blue", lw=1.2, label="Narwhal (azimuthal mean)")
    ref = pic.get("reference")
    if ref:
        ax.plot(ref["x"], ref["y"], "ko", ms=5, label=ref["label"])
    ax.set_xlabel("x / L")
    ax.set_ylabel(pic["column"])
    ax.axhline(0, color="k", lw=0.4)
    ax.legend(fontsize=8)


def _picture_azimuthal(tables, pic, ax):
    """The column against the azimuth from +z at the stations pic["stations"] (x / L), one
    colour per station; the run beside (a peer's) dashed."""
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for (label, t), style in zip(tables, ("-", "--")):
        for n, station in enumerate(pic["stations"]):
            phi, v = around(t, pic["column"], station)
            ax.plot(phi, v, style, color=colours[n % len(colours)], lw=1.2, label=f"{label}, x/L = {station:g}")
    ax.set_xlabel("azimuth from +z [deg]")
    ax.set_ylabel(pic["column"])
    ax.legend(fontsize=7, ncol=2)


def _picture_friction_lines(tables, pic, ax):
    """The first run's skin-friction lines on the body unrolled onto (x, azimuth from
    the windward line, 0 to 180 degrees), and each run's cross-flow separation line
    (body.separation_azimuth; the first solid, a run beside dashed). A line's slope is
    d(phi)/dx = (cf_phi / r) / cf_x, phi in degrees."""
    t = with_crossflow_friction(tables[0][1])
    lines = meridians(t)
    ends = meridian_stations(t, lines)
    x = np.linspace(ends[0], ends[-1], 161)[4:-4]  # the poles' own faces left out
    phi = np.linspace(0.0, 180.0, 91)
    u, v = np.zeros((phi.size, x.size)), np.zeros((phi.size, x.size))
    for n, station in enumerate(x):
        cols = [around(t, c, station, lines) for c in ("cf_x", "cf_phi", "r")]
        a = cols[0][0]
        half = np.argsort(a)[np.sort(a) >= 0.0]
        fx, fp, r = (c[1][half] for c in cols)
        u[:, n] = np.interp(phi, a[half], fx)
        v[:, n] = np.interp(phi, a[half], fp / r) * 180.0 / np.pi
    ax.streamplot(x, phi, u, v, density=1.6, color="0.55", linewidth=0.6, arrowsize=0.6)
    for (label, table), style in zip(tables, ("-", "--")):
        try:
            s = with_crossflow_friction(table)
        except HarnessError:
            continue  # a run without wall shear: no line
        sl = meridians(s)
        ax.plot(x, [separation_azimuth(s, station, sl) for station in x], style, color="tab:red", lw=1.5,
                label=f"{label}: separation line (circumferential cf = 0)")
    ax.set_xlim(x[0], x[-1])
    ax.set_ylim(0.0, 180.0)
    ax.set_xlabel("x / L")
    ax.set_ylabel("azimuth from windward [deg]")
    ax.legend(fontsize=7, loc="lower left")


def _time_history(rung_dir, pic):
    """(time, values, label) of a time_history picture, or None when the run has no such file."""
    name, _, column = pic["column"].partition(":")
    path = rung_dir / "runs" / pic["run"] / f"{name}.csv"
    if not path.exists():
        return None
    t = propulsor_per_step(path.parent) if name == "propulsor" else read_csv(path)
    if name == "motion" and pic.get("gravity") and column in ("vertical_velocity", "horizontal_speed",
                                                               "axis_from_vertical"):
        down, _ = gravity_direction(pic["gravity"], f"picture of run '{pic['run']}'")
        if column == "axis_from_vertical":
            return t["time"], axis_from_vertical_deg(t, down), "axis from vertical [deg]"
        vertical, horizontal = fall_components(t, down)
        return t["time"], vertical if column == "vertical_velocity" else horizontal, column.replace("_", " ")
    if name == "motion" and column in ("rise", "travel") and pic.get("frame"):
        _, travel, rise = water_path(t, _frame(pic))
        return t["time"], rise if column == "rise" else travel, f"{column} through the water [L]"
    return (t["time"], t[column], column) if column in t else None


def _frame(pic):
    f = pic["frame"]
    return np.array(f["origin"]), np.array(f["stream"]), np.array(f["down"])


def _plot_side_view(rung_dir, pic, path):
    """A free body's path through the water seen from the side (kind side_view: travel,
    rise) or from above (plan_view: travel, starboard), with its axis drawn every unit of
    time from nose (dotted) to tail: the body of a unit-length grid from x = 0 to 1 (the
    SUBOFF grids: nose at x = 0, x_B = -x); `beside`: another run, dashed."""
    frame = _frame(pic)
    origin, stream, down = frame
    ahead = -(stream - (stream @ down) * down)
    ahead /= np.linalg.norm(ahead)
    across = -down if pic["kind"] == "side_view" else np.cross(down, ahead)  # up, or starboard
    runs = [(r, style) for r, style in ((pic["run"], "-"), (pic.get("beside"), "--"))
            if r and (rung_dir / "runs" / r / "motion.csv").exists()]
    if not runs:
        return False
    fig, ax = plt.subplots(figsize=(9.0, 3.6) if pic["kind"] == "side_view" else (7.5, 6.5))
    nose = float(origin[0])  # O's distance behind the nose at x = 0
    for n, (run, style) in enumerate(runs):
        m = read_csv(rung_dir / "runs" / run / "motion.csv")
        p, travel, _ = water_path(m, frame)
        side = p @ across
        colour = ("tab:blue", "tab:orange")[n]
        ax.plot(travel, side, style, color=colour, lw=1.2, label=f"Narwhal, {run}: path of O")
        axis = body_axis(m)
        a, b = axis @ ahead, axis @ across
        last = -1.0
        for k, t in enumerate(m["time"]):
            if t - last < 1.0 - 1e-9:
                continue
            last = t
            tail, front = -(1.0 - nose), nose  # the body from its tail to its nose along x_B, O between
            ax.plot([travel[k] + tail * a[k], travel[k] + front * a[k]],
                    [side[k] + tail * b[k], side[k] + front * b[k]], "-", color=colour, lw=2.2, alpha=0.55)
            ax.plot([travel[k] + front * a[k]], [side[k] + front * b[k]], "o", color=colour, ms=3)
    ax.set_aspect("equal")
    ax.set_xlabel("travel through the water [L]")
    ax.set_ylabel("rise [L]" if pic["kind"] == "side_view" else "to starboard [L]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    _title(ax, pic["title"])
    _save(fig, path)
    return True


def _picture_time_history(series, pic, ax):
    time, values, label = series
    ax.plot(time, values, "-", color="tab:blue", lw=1.2, label=f"Narwhal, {pic['run']}")
    ref = pic.get("reference")
    if ref and ref.get("x") is None:
        for n, level in enumerate(ref["y"]):
            ax.axhline(level, color="k", ls="--", lw=0.9, label=ref["label"] if n == 0 else None)
    elif ref:
        ax.plot(ref["x"], ref["y"], "ko", ms=5, label=ref["label"])
    ax.set_xlabel("t")
    ax.set_ylabel(label)
    ax.legend(fontsize=8)


def _wake_panel(run_dir, ax, vmax=None):
    """The flow speed in the plane y = y_O through the body's origin (motion.csv's last
    row): the cells within 8 degrees of it seen from the x axis through the origin (the
    body grids' meridians), x along the fall; returns the scatter and the speeds."""
    m = read_csv(run_dir / "motion.csv")
    origin = np.array([m["x"][-1], m["y"][-1], m["z"][-1]])
    xs, zs, speed = [], [], []
    for z in read_solution(run_dir / "solution.cgns"):
        c = z.centres
        dy, dz = c[..., 1] - origin[1], c[..., 2] - origin[2]
        near = np.abs(dy) < np.tan(np.radians(8.0)) * np.abs(dz) + 1e-3
        near &= np.abs(c[..., 0] - origin[0]) < 8.0
        near &= np.abs(c[..., 2] - origin[2]) < 3.0
        xs.append(c[..., 0][near] - origin[0])
        zs.append(c[..., 2][near] - origin[2])
        speed.append(np.sqrt(z.fields["u"] ** 2 + z.fields["v"] ** 2 + z.fields["w"] ** 2)[near])
    x, zz, s = np.concatenate(xs), np.concatenate(zs), np.concatenate(speed)
    order = np.argsort(s)  # fast cells drawn last
    sc = ax.scatter(x[order], zz[order], c=s[order], s=4.0, cmap="magma", vmin=0.0,
                    vmax=vmax or np.percentile(s, 99.5))
    ax.set_aspect("equal")
    ax.set_xlim(-2.5, 8.0)
    ax.set_ylim(-2.5, 2.5)
    ax.set_title(f"t = {m['time'][-1]:.3g}", fontsize=9)
    return sc, s


def _plot_wake_strip(rung_dir, pic, path):
    runs = [r for r in [pic["run"], *pic.get("then", [])]
            if (rung_dir / "runs" / r / "solution.cgns").exists() and (rung_dir / "runs" / r / "motion.csv").exists()]
    if not runs:
        return False
    fig, axes = plt.subplots(len(runs), 1, figsize=(7.5, 2.9 * len(runs) + 1.2), squeeze=False)
    vmax = None
    for ax, run in zip(axes[:, 0], runs):
        sc, s = _wake_panel(rung_dir / "runs" / run, ax, vmax)
        vmax = vmax or float(np.percentile(s, 99.5))  # one colour scale for the strip
        ax.set_ylabel("z - z_O")
    axes[-1, 0].set_xlabel("x - x_O (the body falls towards -x)")
    fig.suptitle(pic["title"], fontsize=10)
    fig.tight_layout(rect=(0.0, 0.1, 1.0, 1.0))  # room below for the colour bar
    fig.colorbar(sc, cax=fig.add_axes((0.2, 0.06, 0.6, 0.015)), orientation="horizontal",
                 label="flow speed (earth frame)")
    fig.savefig(path, dpi=90)  # laid out above: _save's tight_layout would not place the bar's axes
    plt.close(fig)
    return True


def _plot_picture(rung_dir, pic, path):
    if pic["kind"] in ("side_view", "plan_view"):
        return _plot_side_view(rung_dir, pic, path)
    if pic["kind"] == "wake_strip":
        return _plot_wake_strip(rung_dir, pic, path)
    if pic["kind"] == "time_history":
        series = _time_history(rung_dir, pic)
        if series is None:
            return False
        fig, ax = plt.subplots(figsize=(7.5, 4.2))
        _picture_time_history(series, pic, ax)
        _title(ax, pic["title"])
        _save(fig, path)
        return True
    t = _surface_table(rung_dir, pic)
    if t is None:
        return False
    if pic["kind"] in ("azimuthal", "friction_lines"):
        tables = [(pic["run"], t)]
        other = _surface_table(rung_dir, dict(pic, run=pic["beside"])) if pic.get("beside") else None
        if other is not None:
            tables.append((pic["beside"], other))
        fig, ax = plt.subplots(figsize=(7.5, 4.6))
        (_picture_azimuthal if pic["kind"] == "azimuthal" else _picture_friction_lines)(tables, pic, ax)
    elif pic["kind"] == "surface":
        fig, (ax, below) = plt.subplots(2, 1, figsize=(7.5, 5.6), gridspec_kw={"height_ratios": [1, 2]})
        sc = _picture_surface(t, pic, ax, below)
        fig.colorbar(sc, ax=below, orientation="horizontal", fraction=0.08, pad=0.18,
                     label=pic["column"] + " (colours span its 1st to 99th percentile)")
    else:
        fig, ax = plt.subplots(figsize=(7.5, 4.2))
        _picture_axial(t, pic, ax)
    _title(ax, pic["title"])
    _save(fig, path)
    return True


def _plot_residuals(rung_dir, res, path):
    fig, ax = plt.subplots(figsize=(6.4, 4.0))
    any_line = False
    for r in res.get("runs", []):
        h = rung_dir / "runs" / r["id"] / "history.csv"
        if not h.exists():
            continue
        t = read_csv(h)
        if t["iteration"].size == 0:
            continue
        if "res_p" not in t:  # a peer code's history carries forces only
            continue
        tot = np.sqrt(sum(t[c] ** 2 for c in ("res_p", "res_u", "res_v", "res_w")))
        ax.semilogy(t["iteration"], tot / tot[0], label=r["id"])
        any_line = True
    if not any_line:
        plt.close(fig)
        return False
    ax.set_xlabel("Newton iteration")
    ax.set_ylabel("|R| / |R_0|")
    ax.set_title("residual history")
    if len(res.get("runs", [])) <= 8:
        ax.legend(fontsize=8)
    _save(fig, path)
    return True


def _retreat_note(retreats):
    """What a run's status cell adds when the run went back from divergences (solver.retreats)."""
    if not retreats:
        return ""
    return f" (went back {retreats} time{'s' if retreats > 1 else ''} from a divergence: run.json retreats)"


def _rung_page(rung_dir, res):
    rows = "".join(
        f"<tr><td>{html.escape(r['id'])}</td><td>{html.escape(r.get('peer_version') or r.get('code', 'narwhal'))}</td>"
        f"<td class='{html.escape(str(r.get('status')))}'>{_fmt(r.get('status'))}"
        f"{' (reused from an earlier sitting)' if r.get('reused') else ''}"
        f"{' (continued from the restart of an interrupted sitting)' if r.get('continued') else ''}"
        f"{_retreat_note(r.get('retreats'))}</td>"
        f"<td class=num>{_fmt(r.get('ranks', 1))}</td>"
        f"<td class=num>{_fmt(r.get('iterations'))}</td><td class=num>{_fmt(r.get('wall_seconds'))}</td>"
        f"<td class=num>{_fmt(r.get('cells'))}</td><td class=num>{_fmt(r.get('residual_drop'))}</td>"
        f"<td><a href='{html.escape(r.get('log', ''))}'>log</a></td></tr>" for r in res.get("runs", []))
    body = (f"<p>Status: <span class='{res['status']}'>{res['status'].upper()}</span> — tier {res.get('tier')}, "
            f"{_fmt(res.get('wall_seconds'))} s</p>")
    if res.get("message"):
        body += f"<p>{html.escape(res['message'])}</p>"
    body += ("<h2>Runs</h2><table><tr><th>run</th><th>code</th><th>status</th><th>ranks</th><th>iterations</th><th>wall s</th><th>cells</th>"
             f"<th>residual drop</th><th>log</th></tr>{rows}</table>")
    if _plot_residuals(rung_dir, res, rung_dir / "residuals.png"):
        body += "<img src='residuals.png' alt='residual history'>"
    body += _settings_section(res.get("settings") or {})
    body += _unsteady_points_section(res.get("unsteady_points") or [], rung_dir)
    body += "<h2>Checks</h2>"
    for i, c in enumerate(res.get("checks", [])):
        verdict = "PASS" if c.get("pass") else "FAIL"
        body += (f"<h3>{html.escape(c['name'])} <span class='{verdict}'>{verdict}</span></h3>"
                 "<table><tr><th>comparator</th><th>computed</th><th>reference or bound</th><th>delta</th>"
                 f"<th>tolerance</th></tr><tr><td>{c['comparator']}</td>{_check_cells(c)}</tr></table>"
                 f"<p class=why>Why this tolerance: {html.escape(c['rationale'])}</p>")
        if c.get("orders"):
            body += "<p class=why>Observed orders (coarse to fine): " + ", ".join(f"{o:.3f}" for o in c["orders"]) + "</p>"
        if c.get("extrapolated") is not None:
            body += f"<p class=why>Observed order {c['observed_order']:.3f}; Richardson-extrapolated value {c['extrapolated']:.6g}</p>"
        if c.get("reference_source"):
            body += f"<p class=why>Reference: {html.escape(c['reference_source'])}</p>"
        if c.get("error"):
            body += f"<pre>{html.escape(c['error'])}</pre>"
        if _plot_check(c, rung_dir / f"check_{i}.png"):
            body += f"<img src='check_{i}.png' alt='{html.escape(c['name'])}'>"
    if res.get("pictures"):
        body += "<h2>Pictures</h2>"
        for i, pic in enumerate(res["pictures"]):
            if pic.get("error"):
                body += f"<p>{html.escape(pic['title'])}: {html.escape(pic['error'])}</p>"
            try:
                drawn = _plot_picture(rung_dir, pic, rung_dir / f"picture_{i}.png")
            except HarnessError as e:  # a run's files that disagree: said on the page, the report goes on
                body += f"<p>{html.escape(pic['title'])}: {html.escape(str(e))}</p>"
                continue
            if drawn:
                body += f"<img src='picture_{i}.png' alt='{html.escape(pic['title'])}'>"
                if pic.get("reference"):
                    body += f"<p class=why>Reference points: {html.escape(pic['reference']['source'])}</p>"
            else:
                body += f"<p>{html.escape(pic['title'])}: run '{html.escape(pic['run'])}' left no surface file</p>"
    if res.get("reported"):
        body += _reported_section(res["reported"], rung_dir)
    prov = res.get("provenance", {})
    body += "<h2>Provenance</h2><table>" + "".join(
        f"<tr><th>{html.escape(k)}</th><td>{_fmt(v)}</td></tr>" for k, v in prov.items()) + "</table>"
    (rung_dir / "index.html").write_text(_page(f"{res['rung']}: {res.get('title', '')}", body, depth=1))


def _settings_section(by_run):
    """The solver settings of the rung's Narwhal runs: one table of those they share, and
    each one that differs with its value per run."""
    if not by_run:
        return ""
    shared, differing = split_settings(by_run)
    n = len(by_run)
    if differing:
        lead = (f"<p>{len(differing)} setting(s) differ between the {n} runs: "
                f"{html.escape(', '.join(differing))}.</p>")
    else:
        lead = f"<p>One set of settings for all {n} run(s) (from each run's run.json).</p>"
    body = "<h2>Solver settings</h2>" + lead + "<table><tr><th>setting</th><th>value</th></tr>" + "".join(
        f"<tr><td>{html.escape(k)}</td><td>{_fmt(v)}</td></tr>" for k, v in shared.items())
    body += "".join(
        f"<tr><td>{html.escape(k)}</td><td class=FAIL>" + "; ".join(
            f"{html.escape(rid)}: {_fmt(v) if v is not None else 'not set'}" for rid, v in values.items())
        + "</td></tr>" for k, values in differing.items())
    return body + "</table>"


def _unsteady_points_section(sweeps, rung_dir):
    """Each sweep's rule for points whose steady iteration ends with the forces swinging, and
    the points that went on in physical time under it, with a plot of their histories."""
    if not sweeps:
        return ""
    body = "<h2>Points continued in physical time</h2>"
    for s in sweeps:
        settings = ", ".join(f"{html.escape(k)} = {html.escape(v)}" for k, v in s["set"].items())
        body += (f"<p>Sweep <b>{html.escape(s['sweep'])}</b>: a point whose steady run ends with a force span above "
                 f"{_fmt(s['force_span'])} goes on from its last state with {settings}; its values are the means "
                 f"over the whole periods of its forces' swing after the first {_fmt(s['discard'])} time units, its "
                 "iteration band the standard error of that mean from the single periods' means.</p>")
        if not s["points"]:
            body += "<p>No point needed it.</p>"
            continue
        body += "<table><tr><th>point</th><th>continued in</th><th>whole periods</th><th>averaged over t</th>" \
                "<th>force span (twice the mean's standard error)</th></tr>"
        for p in s["points"]:
            if "error" in p:
                body += (f"<tr><td>{html.escape(p['point'])}</td>"
                         f"<td colspan=4 class=FAIL>{html.escape(p['error'])}</td></tr>")
                continue
            periods = p["periods"] or "none found: the window's mean"
            body += (f"<tr><td>{html.escape(p['point'])}</td><td>{html.escape(p['run'])}</td><td>{periods}</td>"
                     f"<td>{_fmt(p['start'])} to {_fmt(p['end'])}</td><td>{_fmt(p['force_span'])}</td></tr>")
        body += "</table>"
        drawn = [p for p in s["points"] if "history" in p]
        if drawn:
            name = f"unsteady_{s['sweep']}.png"
            _plot_continuations(drawn, rung_dir / name)
            body += f"<img src='{html.escape(name)}' alt='histories of the points continued in physical time'>"
    return body


def _plot_continuations(points, path):
    """Each continued point's history of the column whose rises bound its periods, the
    stretch its means are over shaded."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for i, p in enumerate(points):
        h, colour = p["history"], f"C{i % 10}"
        ax.plot(h["t"], h["y"], color=colour, lw=1.0, label=f"{p['point']}: {h['column']}")
        ax.axvspan(p["start"], p["end"], color=colour, alpha=0.08)
    ax.set_xlabel("t (L / U) from the steady run's end")
    ax.set_ylabel("coefficient (steps.csv, grid axes)")
    ax.legend(fontsize=8)
    _title(ax, "points continued in physical time (shaded: the whole periods averaged)")
    _save(fig, path)


def _reported_value(q):
    if q.get("value") is not None:
        return _fmt(q["value"])
    if q.get("curve"):
        return "plotted below"
    return html.escape(q.get("error", ""))


def _plot_reported_curve(q, path):
    """A reported curve (a sweep's coefficient against the swept variable): points joined,
    with their iteration bands as error bars when the curve has them."""
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    c = q["curve"]
    if c.get("yerr") is not None:
        ax.errorbar(c["x"], c["y"], yerr=c["yerr"], fmt="o-", ms=4, capsize=3, color="tab:blue",
                    label="Narwhal (bars: half the range over the last iterations, or a time mean's standard error)")
        ax.legend(fontsize=8)
    else:
        ax.plot(c["x"], c["y"], "o-", ms=4, color="tab:blue", label="Narwhal")
    ax.axhline(0, color="k", lw=0.5)
    ax.set_xlabel(q["curve"].get("label", "").partition(" vs ")[2] or "x")
    ax.set_ylabel(q.get("unit") or q["name"])
    _title(ax, q["name"])
    _save(fig, path)


def _reported_section(reported, rung_dir):
    body = ("<h2>Reported (no reference, no tolerance)</h2><table><tr><th>quantity</th><th>value</th>"
            "<th>unit</th></tr>" + "".join(
                f"<tr><td>{html.escape(q['name'])}</td><td class=num>{_reported_value(q)}</td>"
                f"<td>{html.escape(q.get('unit', ''))}</td></tr>" for q in reported) + "</table>")
    for i, q in enumerate(reported):
        if q.get("curve"):
            _plot_reported_curve(q, rung_dir / f"reported_{i}.png")
            body += f"<img src='reported_{i}.png' alt='{html.escape(q['name'])}'>"
    return body


def _perf_history(reports, tier):
    """(run-id, rung, wall seconds) from every earlier report of the same tier."""
    out = []
    for d in sorted(Path(reports).iterdir()):
        if not d.is_dir() or d.name == "latest":
            continue
        for rj in d.glob("*/results.json"):
            try:
                r = json.loads(rj.read_text())
            except (OSError, json.JSONDecodeError):
                continue
            # A resumed rung's time is not one sitting's: it stays out of the timing trend.
            resumed = any(x.get("reused") for x in r.get("runs", []))
            if r.get("tier") == tier and r.get("status") == "passed" and not resumed:
                out.append((d.name, r["rung"], r.get("wall_seconds", 0.0)))
    return out


def _benchmark_section(out, history_dir):
    """Kernel benchmark history with regression flags (harness/perf.py)."""
    from . import perf
    if not history_dir or not Path(history_dir).exists():
        return ""
    entries = perf.load(history_dir)
    if not entries:
        return ""
    flags = perf.regressions(entries)
    rows = ""
    for name, (now, ref, ratio, v) in sorted(flags.items()):
        verdict = {"REGRESSION": "<span class=FAIL>REGRESSION</span>",
                   "noisy": "<span class=why>slower, within 3x its noise</span>"}.get(v, "<span class=PASS>ok</span>")
        rows += (f"<tr><td>{html.escape(name)}</td><td class=num>{now / 1e6:.4g}</td>"
                 f"<td class=num>{_fmt(ref / 1e6 if ref else None)}</td><td class=num>{_fmt(ratio)}</td>"
                 f"<td>{verdict}</td></tr>")
    body = ("<h2>Kernel benchmarks</h2><p class=why>Newest run against the rolling median of up to five earlier "
            "runs on the same machine; flagged when more than 15 % slower, or more than three times the benchmark's own "
            "coefficient of variation in this run when that is larger.</p>"
            "<table><tr><th>benchmark</th><th>median ms</th><th>rolling median ms</th><th>ratio</th><th></th></tr>"
            f"{rows}</table>")
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    names = sorted(flags)
    for name in names:
        pts = [(i, e["median_ns"][name]) for i, e in enumerate(entries) if name in e["median_ns"]]
        if pts:
            ax.plot([p[0] for p in pts], [p[1] / pts[0][1] for p in pts], "o-", label=name, ms=3)
    ax.set_xticks(range(len(entries)))
    ax.set_xticklabels([e["git_sha"][:7] for e in entries], rotation=30, ha="right", fontsize=7)
    ax.set_ylabel("median time / first run")
    ax.set_title("kernel benchmark history")
    ax.legend(fontsize=6)
    _save(fig, out / "bench_history.png")
    return body + "<img src='bench_history.png' alt='benchmark history'>"


def _peer_section(reports, out):
    """OpenFOAM vs Narwhal on the laminar flat plate (benchmarks/peer), when measured."""
    pj = Path(reports) / "peer" / "peer.json"
    if not pj.exists():
        return ""
    p = json.loads(pj.read_text())
    runs = p.get("runs")
    if runs is None:  # an older peer.json: say so rather than guess its layout
        return "<h2>Peer benchmark</h2><p class=why>peer.json predates the current format; rerun benchmarks/peer.</p>"
    rows = ""
    for key, r in runs.items():
        rows += (f"<tr><td>{html.escape(r['description'])}</td><td class=num>{r['cells']}</td>"
                 f"<td class=num>{100 * r['cf_max_error']:.3f}</td><td class=num>{100 * r['cf_rms_error']:.3f}</td>"
                 f"<td class=num>{r['iterations']}</td><td class=num>{r['wall_seconds']:.2f}</td>"
                 f"<td class=num>{len(r.get('wall_seconds_all', [1]))}</td></tr>")
    fig, ax = plt.subplots(figsize=(7.5, 4.0))
    for key, r in runs.items():
        prof = r.get("cf_error_profile")
        if prof and key in ("openfoam", "openfoam_coarse", "narwhal_peer", "narwhal_multigrid"):
            ax.plot([q[0] for q in prof], [100 * q[1] for q in prof], "o-" if "openfoam" in key else "s-",
                    ms=3, label=f"{key} ({r['cells']} cells)")
    ax.axhline(0.0, color="k", lw=0.5)
    ax.set_xlabel("x / L")
    ax.set_ylabel("Cf / Cf_Blasius - 1 [%]")
    ax.legend(fontsize=7)
    _save(fig, out / "peer_cf_error.png")
    nw = runs.get("narwhal_peer", {})
    verdict = "yes" if p.get("narwhal_reaches_openfoam_accuracy") else "no"
    ratios = ", ".join(f"{x:.1f}" for x in p.get("time_ratios_same_repetition", []))
    return (f"<h2>Peer benchmark: laminar flat plate, OpenFOAM and Narwhal in the same run</h2>"
            "<table><tr><th>run</th><th>cells</th><th>max |Cf error| %</th><th>RMS Cf error %</th><th>iterations</th>"
            f"<th>median wall s</th><th>repetitions</th></tr>{rows}</table>"
            "<img src='peer_cf_error.png' alt='Cf error against Blasius, both codes'>"
            f"<p class=why>Narwhal (coarser or equal grid) reaches OpenFOAM's R1 Cf accuracy, max and RMS over "
            f"0.1 &lt; x &lt; 0.9: {verdict}; OpenFOAM wall time / Narwhal wall time (medians): "
            f"{p['time_ratio_openfoam_over_narwhal']:.2f}, per repetition {ratios} (target: at least 5). "
            f"Iteration error left in Narwhal's Cf at its stop: {nw.get('iteration_error', float('nan')):.1e} "
            "(relative, against its run to a 1e-10 drop).</p>")


def _perf_page(out, reports, results, history_dir=None):
    tier = results[0].get("tier") if results else None
    rows = ""
    for r in results:
        runs = r.get("runs", [])
        work = sum((x.get("cells") or 0) * (x.get("iterations") or 0) for x in runs)
        solver_s = sum(x.get("wall_seconds") or 0 for x in runs)
        rate = work / solver_s if solver_s > 0 else None
        rows += (f"<tr><td><a href='{r['rung']}/index.html'>{html.escape(r['rung'])}</a></td>"
                 f"<td class=num>{_fmt(r.get('wall_seconds'))}</td><td class=num>{_fmt(solver_s)}</td>"
                 f"<td class=num>{_fmt(r.get('cells'))}</td><td class=num>{_fmt(r.get('iterations'))}</td>"
                 f"<td class=num>{_fmt(rate)}</td></tr>")
    body = ("<table><tr><th>rung</th><th>rung wall s</th><th>solver wall s</th><th>cells (all runs)</th>"
            f"<th>iterations (all runs)</th><th>cell-iterations / s</th></tr>{rows}</table>")
    hist = _perf_history(reports, tier) if tier else []
    if hist:
        fig, ax = plt.subplots(figsize=(7.5, 4.2))
        ids = sorted({h[0] for h in hist})
        for rung in sorted({h[1] for h in hist}):
            pts = [(ids.index(h[0]), h[2]) for h in hist if h[1] == rung]
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=rung)
        ax.set_xticks(range(len(ids)))
        ax.set_xticklabels(ids, rotation=30, ha="right", fontsize=7)
        ax.set_ylabel("rung wall time [s]")
        ax.set_title(f"wall time per rung, tier {tier} (reports in {Path(reports).name}/)")
        ax.legend(fontsize=7)
        _save(fig, out / "perf_history.png")
        body += "<h2>History</h2><img src='perf_history.png' alt='performance history'>"
    body += _peer_section(reports, out)
    body += _benchmark_section(out, history_dir)
    body += ("<p class=why>Wall times on a shared 2-core machine are noisy; compare ratios and medians, "
             "never a single run.</p>")
    (out / "perf.html").write_text(_page("Performance", body))


def _screenshots(out, results):
    """Pictures of the summary and the flat-plate page kept with the report (when chromium exists)."""
    if not browser.chromium():
        return
    shots = out / "screenshots"
    shots.mkdir(exist_ok=True)
    browser.screenshot(out / "index.html", shots / "summary.png", 1280, 1000)
    for r in results:
        if r["rung"].startswith("flat_plate"):
            browser.screenshot(out / r["rung"] / "index.html", shots / f"{r['rung']}.png", 1280, 3000)


def _ladder_table(results):
    """The paper's whole ladder, step by step: the rungs of this run with their status,
    rungs of other tiers, and the steps not built yet with the issue that builds them."""
    by_rung = {r["rung"]: r for r in results}
    rows = ""
    for n, step in enumerate(load_ladder(), 1):
        if step.planned:
            rows += (f"<tr><td class=num>{n}</td><td>{html.escape(step.title)}</td><td>—</td>"
                     f"<td class=notbuilt>not built yet ({html.escape(step.planned)})</td></tr>")
            continue
        cells, states = [], []
        for name in step.rungs:
            r = by_rung.get(name)
            state = r["status"] if r else "not in this run"
            states.append(state)
            link = f"<a href='{name}/index.html'>{html.escape(name)}</a>" if r else html.escape(name)
            cells.append(f"{link} <span class='{html.escape(state.replace(' ', ''))}'>{html.escape(state)}</span>")
        ran = [s for s in states if s != "not in this run"]
        overall = ("not in this run" if not ran else "passed" if all(s in ("passed", "skipped") for s in ran)
                   else "failed")
        rows += (f"<tr><td class=num>{n}</td><td>{html.escape(step.title)}</td><td>{'<br>'.join(cells)}</td>"
                 f"<td class='{overall.replace(' ', '')}'>{overall}</td></tr>")
    return ("<h2>The validation ladder</h2><table><tr><th>step</th><th>what it validates</th><th>rungs</th>"
            f"<th>status</th></tr>{rows}</table>")


def build_report(out, reports, history_dir=None):
    out, reports = Path(out), Path(reports)
    results = []
    for rj in sorted(out.glob("*/results.json")):
        try:
            results.append(json.loads(rj.read_text()))
        except json.JSONDecodeError as e:
            results.append({"rung": rj.parent.name, "status": "crashed", "checks": [],
                            "message": f"unreadable results.json: {e}"})
    rows = ""
    for r in results:
        _rung_page(out / r["rung"], r)
        link = f"<a href='{r['rung']}/index.html'>{html.escape(r['rung'])}</a>"
        checks = r.get("checks") or [None]
        for i, c in enumerate(checks):
            first = f"<td rowspan={len(checks)}>{link}<br><span class='{r['status']}'>{r['status']}</span></td>" if i == 0 else ""
            t = f"<td rowspan={len(checks)} class=num>{_fmt(r.get('wall_seconds'))}</td>" if i == 0 else ""
            if c is None:
                rows += f"<tr>{first}<td colspan=6>{html.escape(r.get('message', 'no checks ran'))}</td>{t}</tr>"
                continue
            v = "PASS" if c.get("pass") else "FAIL"
            rows += f"<tr>{first}<td>{html.escape(c['name'])}</td>{_check_cells(c)}<td class={v}>{v}</td>{t}</tr>"
    passed = sum(r["status"] == "passed" for r in results)
    sha = next((r.get("provenance", {}).get("git_sha") for r in results if r.get("provenance")), "unknown")
    skipped = sum(r["status"] == "skipped" for r in results)
    body = (f"<p>{passed} of {len(results)} rungs passed{f', {skipped} skipped' if skipped else ''} — run "
            f"{html.escape(out.name)}, git {html.escape(str(sha))}</p>" + _ladder_table(results) +
            "<h2>Checks</h2><table><tr><th>rung</th><th>check</th><th>computed</th><th>reference or bound</th>"
            f"<th>delta</th><th>tolerance</th><th>result</th><th>time s</th></tr>{rows}</table>")
    (out / "index.html").write_text(_page("Narwhal validation report", body))
    _perf_page(out, reports, results, history_dir)
    _screenshots(out, results)
    latest = reports / "latest"
    if latest.exists():
        shutil.rmtree(latest)
    shutil.copytree(out, latest, ignore=shutil.ignore_patterns("*.h5", "*.cgns"))
    return out / "index.html"
