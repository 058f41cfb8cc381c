#!/usr/bin/python3
"""oovr's report: plots and one HTML page from an oovr results database.

`oovr report RESULTS.db --out DIR` writes this script into DIR with claims.json
(the paper's claims with oovr's values as oovr measured them in the database,
the runs on the paper's machine, the order schemes are drawn in) and runs it
with Debian's Python and matplotlib; to draw the page again after editing it
(the database unchanged):  /usr/bin/python3 DIR/report.py RESULTS.db DIR
(docs/report.md describes what it draws).
"""
import html
import json
import math
import os
import re
import sqlite3
import sys
import urllib.parse

import matplotlib

matplotlib.use("Agg")
import matplotlib.lines as mlines  # noqa: E402
import matplotlib.patches as mpatches  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

FIXED = {"id", "sweep", "position", "scene", "scheme", "resolution", "frame", "frames", "aniso", "config", "checksum",
         "status", "error", "oovr_version", "git_commit", "command", "host", "started", "wall_s", "result"}
# The order schemes are drawn in: the registered schemes' order (the paper's
# first), which oovr writes beside the claims; then any other by name.
ORDER = []
MAX_IMAGE_RUNS = 12
RUN_ID = re.compile(r"[0-9a-f]{16}")


def scheme_rank(s):
    return (ORDER.index(s) if s in ORDER else len(ORDER), s)


# ---------------------------------------------------------------- units

def scale_for(unit, values):
    """(divisor, label) that shows `values` in `unit` readably."""
    finite = [abs(v) for v in values if isinstance(v, (int, float)) and math.isfinite(v) and v != 0]
    top = max(finite) if finite else 1
    if unit == "B/s":
        return (1e9, "GB/s") if top < 1e12 else (1e12, "TB/s")
    if unit == "B":
        for d, u in ((1e9, "GB"), (1e6, "MB"), (1e3, "KB")):
            if top >= d:
                return d, u
        return 1, "B"
    if unit == "s":
        for d, u in ((1, "s"), (1e-3, "ms"), (1e-6, "µs")):
            if top >= d:
                return d, u
        return 1e-9, "ns"
    if unit == "Hz":
        return (1e6, "MHz") if top < 1e9 else (1e9, "GHz")
    if unit == "J":
        for d, u in ((1, "J"), (1e-3, "mJ"), (1e-6, "µJ")):
            if top >= d:
                return d, u
        return 1e-9, "nJ"
    return 1, unit


def readable(entry):
    """A configuration entry's readable value."""
    return entry.get("value", "") if isinstance(entry, dict) else str(entry)


# ---------------------------------------------------------------- data

def load(db):
    # Read-only, by a URI whose path is quoted (a '?' or '#' in it is a name).
    con = sqlite3.connect("file:" + urllib.parse.quote(os.path.abspath(db)) + "?mode=ro", uri=True)
    cols = [r[1] for r in con.execute("PRAGMA table_info(runs)")]
    swept_cols = [c for c in cols if c not in FIXED]
    runs = {}
    for row in con.execute("SELECT * FROM runs ORDER BY sweep, position"):
        r = dict(zip(cols, row))
        r["config"] = json.loads(r["config"])
        r["result"] = json.loads(r["result"]) if r["result"] else None
        r["swept"] = {c: r[c] for c in swept_cols if r.get(c) is not None}
        r["m"] = {}
        # oovr checked the database before running this script; an id is
        # still checked here, as it becomes a file name and a link.
        if not isinstance(r["id"], str) or not RUN_ID.fullmatch(r["id"]):
            sys.exit("a run id that is not oovr's: {!r}".format(r["id"]))
        runs[r["id"]] = r
    for run, loc, metric, value, unit in con.execute("SELECT run, location, metric, value, unit FROM metrics"):
        if run in runs:
            runs[run]["m"][(loc, metric)] = (value, unit)
    sweeps = []
    for name, file, definition, keys, points, command in con.execute(
            "SELECT name, file, definition, swept_keys, points, command FROM sweeps ORDER BY name"):
        sweeps.append({"name": name, "file": file, "definition": definition, "keys": json.loads(keys),
                       "points": points, "command": command})
    return con, runs, sweeps


def metric(run, loc, name):
    v = run["m"].get((loc, name))
    return v[0] if v else float("nan")


def config_value(run, key):
    e = run["config"].get(key)
    if not isinstance(e, dict):
        return None
    return e["base"] if "base" in e else e.get("value")


def group_key(run):
    return (run["scene"], run["resolution"], run["frame"], run["aniso"])


def geomean(values):
    v = [x for x in values if isinstance(x, (int, float)) and math.isfinite(x) and x > 0]
    return math.exp(sum(math.log(x) for x in v) / len(v)) if v else float("nan")


def claim_values(claims):
    """For each claim value: oovr's ratio per (scene, resolution), as oovr
    measured it in the database (claims.h, measure_claims)."""
    out = []
    for claim in claims:
        for v in claim["values"]:
            out.append((claim, v, {(scene, res): x for scene, res, x in v["measured"]}))
    return out


def form(value, how):
    if not isinstance(value, (int, float)) or not math.isfinite(value):
        return "n/a"
    if how == "percent":
        p = (value - 1) * 100
        return "0%" if abs(p) < 0.5 else "{:+.0f}%".format(p)  # as the comparison document writes it
    if how == "bits":
        return "{:.0f} bits".format(value)
    return "{:.2f}x".format(value)


# ---------------------------------------------------------------- plots

def save(fig, out, name, layout=True):
    if layout:
        fig.tight_layout()
    for ext in ("png", "svg", "pdf"):
        fig.savefig(os.path.join(out, name + "." + ext), dpi=110)
    plt.close(fig)
    return name


def frames_of(run):
    """The run's per-frame latencies, seconds (empty when not stored)."""
    res = run.get("result") or {}
    v = res.get("frame_latencies_s") or res.get("frame_latencies") or []
    return [x for x in v if isinstance(x, (int, float)) and math.isfinite(x)]


def slug(text):
    s = "".join(c if c in "abcdefghijklmnopqrstuvwxyz0123456789" else "-" for c in text.lower())
    while "--" in s:
        s = s.replace("--", "-")
    return s.strip("-")[:60]


def claim_figures(values, out):
    """One plot per paper figure: oovr's ratio per scene beside the paper's."""
    figures = {}
    for claim, v, per in values:
        figures.setdefault(claim["figure"], []).append((claim, v, per))
    made = []
    for title, items in figures.items():
        items = [(c, v, per) for c, v, per in items if per]
        if not items:
            continue
        groups = sorted({g for _, _, per in items for g in per})
        # A colour per scene and a hatch per resolution, so that the legend
        # names each once (a scene at three resolutions is not three
        # entries), beside the plot rather than over the bars.
        scenes = sorted({g[0] for g in groups})
        resolutions = sorted({g[1] for g in groups}, key=lambda r: [int(x) for x in r.split("x")] if "x" in r else [0])
        hatches = ["", "///", "...", "xxx", "\\\\"]
        fig, ax = plt.subplots(figsize=(max(5.0, 1.3 * len(items) + 2) + 2.2, 3.8))
        width = 0.8 / (len(groups) + 1)
        for gi, g in enumerate(groups):
            xs = [i + (gi - len(groups) / 2) * width for i in range(len(items))]
            ys = [per.get(g, float("nan")) for _, _, per in items]
            ax.bar(xs, ys, width, color=PALETTE[scenes.index(g[0]) % len(PALETTE)],
                   hatch=hatches[resolutions.index(g[1]) % len(hatches)], edgecolor="white", linewidth=0)
        handles = [mpatches.Patch(color=PALETTE[k % len(PALETTE)], label="oovr: " + sc) for k, sc in enumerate(scenes)]
        if len(resolutions) > 1:
            handles += [mpatches.Patch(facecolor="lightgrey", hatch=hatches[k % len(hatches)], edgecolor="white", label=res)
                        for k, res in enumerate(resolutions)]
        px = [i + (len(groups) / 2) * width for i in range(len(items))]
        py = [v.get("paper", float("nan")) for _, v, _ in items]
        if any(math.isfinite(p) for p in py):
            handles.append(ax.scatter(px, py, marker="D", s=48, color="black", zorder=3, label="the paper"))
        ax.set_xticks(range(len(items)))
        ax.set_xticklabels(["{}: {}".format(c["id"], v["label"]) for c, v, _ in items], rotation=20, ha="right", fontsize=8)
        measures = sorted({v["measure"] for _, v, _ in items})
        unit = "bits" if measures == ["engine_storage"] else "ratio (x)"
        words = {"speedup": "speed-up", "latency": "latency", "throughput": "throughput", "traffic": "inter-GPM traffic",
                 "best_to_worst": "best-to-worst GPM time", "energy": "memory-system energy", "link_energy": "link energy"}
        ax.set_ylabel("{} ({})".format(", ".join(words.get(m, m) for m in measures), unit) if unit != "bits"
                      else "storage (bits)", fontsize=8)
        if unit != "bits":
            ax.axhline(1.0, color="grey", lw=0.8)
        ax.set_title(title, fontsize=10)
        ax.legend(handles=handles, fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
        made.append((title, save(fig, out, "paper-" + slug(title))))
    return made


# One colour per scheme, the same in every figure: oovr's (claims.json's
# scheme_colours, which its paper charts use too: svg_chart.h), else the
# registered schemes in their order, then any other by a stable hash of its
# name (twenty colours of tab20, which repeats no colour within a figure of
# up to twenty schemes). The other swept keys' values are told apart by
# line style and marker.
COLOURS = {}
PALETTE = [matplotlib.colormaps["tab20"](i) for i in (0, 2, 4, 6, 8, 10, 12, 14, 16, 18, 1, 3, 5, 7, 9, 11, 13, 15, 17, 19)]
STYLES = ["-", "--", ":", "-."]
MARKERS = ["o", "s", "^", "D", "v", "P"]


def scheme_colour(scheme):
    if scheme in COLOURS:
        return COLOURS[scheme]
    if scheme in ORDER:
        return PALETTE[ORDER.index(scheme) % len(PALETTE)]
    return PALETTE[(len(ORDER) + sum(scheme.encode()) * 7) % len(PALETTE)]


def numeric(value):
    """A sort key that orders numbers as numbers (32 before 128), then text."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return (0, float(value), "")
    return (1, 0.0, str(value))


def swept_lines(runs, key, extra=()):
    """The lines of a figure against `key`: runs that differ in `key` alone
    (their scene, resolution, scheme and every other configuration key
    equal), each line's runs in increasing `key`. Runs differing in another
    key (another swept value, an ablation, a preset) are other lines, never
    joined. `extra`: runs that do not sweep `key` but hold a value of it
    (the sweep's main grid at the default), each added to the line whose
    other keys it equals, if there is one. Returns [(scheme, others, runs)],
    `others` the keys that tell a line from its scheme's others ("k=v,
    ..."), lines by scene and resolution, then in scheme order, then
    numerically by those values."""
    groups = {}
    ident = lambda r: (r["scene"], r["resolution"], r["scheme"],
                       tuple(sorted((k, json.dumps(config_value(r, k))) for k in r["config"] if k != key)))
    for r in runs:
        groups.setdefault(ident(r), []).append(r)
    for r in extra:
        g = groups.get(ident(r))
        if g is not None and all(x["swept"][key] != config_value(r, key) for x in g):
            g.append(dict(r, swept=dict(r["swept"], **{key: config_value(r, key)})))
    by_scheme = {}
    for (scene, res, scheme, cfg), rs in groups.items():
        by_scheme.setdefault((scene, res, scheme), []).append((dict(cfg), rs))
    lines = []
    for (scene, res, scheme), members in by_scheme.items():
        # The keys in which this scheme's lines differ, named on each.
        differing = sorted({k for cfg, _ in members for k in cfg if len({c.get(k) for c, _ in members}) > 1})
        for cfg, rs in members:
            values = [json.loads(cfg[k]) if k in cfg else None for k in differing]
            others = ", ".join("{}={}".format(k, readable(rs[0]["config"].get(k))) for k in differing)
            lines.append(((scene, res), scheme_rank(scheme), [numeric(v) for v in values], scheme, others,
                          sorted(rs, key=lambda r: numeric(r["swept"][key]))))
    lines.sort(key=lambda x: (x[0], x[1], x[2]))
    return [(scheme, others, rs) for _, _, _, scheme, others, rs in lines]


def tick_label(value, unit):
    """A swept value as people write it: 32, 64, ... GB/s, then 1 TB/s."""
    if unit == "B/s":
        return "{:g} TB/s".format(value / 1e12) if value >= 1e12 else "{:g}".format(value / 1e9)
    if unit in ("B", "s", "J"):
        d, u = scale_for(unit, [value])
        return "{:g} {}".format(value / d, u)
    return "{:g}".format(value)


def reference_index(runs):
    """Done runs by (scene, resolution, first frame, filtering), in the
    order a reference is looked for: the database's sweeps, then positions."""
    index = {}
    for r in sorted(runs, key=lambda r: (r["sweep"], r["position"])):
        if r["status"] == "done":
            index.setdefault(group_key(r), []).append(r)
    return index


def reference_of(run, scheme, index):
    """The run of `scheme` on `run`'s setup: the same scene, resolution,
    first frame and filtering, and every configuration key both runs read
    equal (a key one scheme reads alone, its own, is no difference); the
    run itself when it is of `scheme`; None when the database has none."""
    if run["scheme"] == scheme:
        return run
    for c in index.get(group_key(run), ()):
        if c["scheme"] == scheme and all(json.dumps(config_value(c, k)) == json.dumps(config_value(run, k))
                                         for k in run["config"] if k in c["config"]):
            return c
    return None


# What a study's figures can show, one row of panels each (oovr report
# --plots): (name, the y axis's words, the value and its spread for a run).
# Spread: the lowest and highest of the measured frames, where a run
# stores them; a speed-up's, frame by frame over the reference's frames
# when both measured the same number.
def _latency(run, ref):
    y = metric(run, "frame", "latency")
    f = frames_of(run)
    return y, (min(f), max(f)) if f else None


def _speedup(run, ref):
    if ref is None:
        return float("nan"), None
    y = metric(ref, "frame", "latency") / metric(run, "frame", "latency")
    a, b = frames_of(ref), frames_of(run)
    per = [x / z for x, z in zip(a, b) if z > 0] if a and len(a) == len(b) else []
    return y, (min(per), max(per)) if per else None


PLOTS = {
    "latency": ("frame latency ({u}; bars: frames' range)", "s", _latency),
    "speedup": ("speed-up over {ref} (x; bars: frames' range)", "", _speedup),
    "throughput": ("throughput (frames/s)", "", lambda r, ref: (metric(r, "frame", "throughput"), None)),
    "traffic": ("inter-GPM traffic ({u} per frame)", "B", lambda r, ref: (metric(r, "frame", "inter_gpm_bytes"), None)),
    "energy": ("memory-system energy ({u} per frame)", "J", lambda r, ref: (metric(r, "frame", "energy"), None)),
}
DEFAULT_PLOTS = ["latency", "speedup", "traffic", "energy"]


def options_of(claims):
    """The drawing options oovr report wrote beside the claims (checked
    there): which rows, against which keys, panels per scene or per
    scheme, the scheme speed-ups are over, and whether absolute rows keep
    each panel's own y axis."""
    o = claims.get("options") or {}
    out = {"plots": o.get("plots") or DEFAULT_PLOTS, "x": o.get("x") or [], "group": o.get("group") or "scene",
           "normalise": o.get("normalise") or "baseline", "own_y": bool(o.get("own_y")),
           "explicit_plots": bool(o.get("plots"))}
    for p in out["plots"]:
        if p not in PLOTS:
            sys.exit("unknown plot {!r} (one of {})".format(p, ", ".join(PLOTS)))
    if out["group"] not in ("scene", "scheme"):
        sys.exit("unknown grouping {!r} (scene or scheme)".format(out["group"]))
    return out


def swept_figures(sweep, runs, out, options=None):
    """Per swept key: one row of panels per plot (frame latency, speed-up
    over a chosen scheme, throughput, inter-GPM traffic, energy; oovr
    report --plots) against its value; one panel per scene and resolution
    with a line per scheme and setting (swept_lines), or (--group scheme)
    one panel per scheme with a line per scene. One colour per scheme (or
    per scene) in every figure and a line style per setting; bars from the
    frames' lowest to highest value; each row's panels share their y axis
    (absolute rows keep their own with --own-y); the legend beside the
    panels. Bandwidths read 32, 64, ... GB/s and 1 TB/s on a log axis;
    whole-number keys (GPM counts) are evenly spaced categories."""
    o = options or options_of({})
    mine = [r for r in runs.values() if r["sweep"] == sweep["name"] and r["status"] == "done"]
    index = reference_index(runs.values())
    made = []
    for key in sweep["keys"]:
        if o["x"] and key not in o["x"]:
            continue
        pts = [r for r in mine if isinstance(r["swept"].get(key), (int, float))]
        # The sweep's other runs at a value of `key` (its main grid, at the
        # default), to complete the lines they belong to.
        rest = [r for r in mine if key not in r["swept"] and isinstance(config_value(r, key), (int, float))]
        by_scene = {}
        for pan in sorted({(r["scene"], r["resolution"]) for r in pts}):
            by_scene[pan] = swept_lines([r for r in pts if (r["scene"], r["resolution"]) == pan], key,
                                        [r for r in rest if (r["scene"], r["resolution"]) == pan])
        values = sorted({r["swept"][key] for ls in by_scene.values() for _, _, rs in ls for r in rs})
        if len(values) < 2:
            continue
        # Panels and the lines in each: (title, [(colour key, label, others, runs)]).
        if o["group"] == "scheme":
            scenes = list(by_scene)
            panels = {}
            for pan, ls in by_scene.items():
                for scheme, others, rs in ls:
                    panels.setdefault(scheme, []).append((scenes.index(pan), "{}, {}".format(*pan), others, rs))
            panels = [(scheme, panels[scheme]) for scheme in sorted(panels, key=scheme_rank)][:6]
            colour = lambda c: PALETTE[c % len(PALETTE)]
        else:
            panels = [("{}, {}".format(*pan), [(scheme, scheme, others, rs) for scheme, others, rs in ls])
                      for pan, ls in by_scene.items()][:6]
            colour = scheme_colour
        # Rows: the plots asked for that have a value here (the default
        # rows a database cannot fill, a speed-up without its reference
        # scheme or an energy stored before oovr counted it, are left out).
        rows = []
        for p in o["plots"]:
            ys = [PLOTS[p][2](r, reference_of(r, o["normalise"], index))[0] for _, ls in panels for _, _, _, rs in ls
                  for r in rs]
            if any(math.isfinite(y) for y in ys) or o["explicit_plots"]:
                rows.append((p, [y for y in ys if math.isfinite(y)]))
        if not rows:
            continue
        unit = next((r["config"][key].get("unit", "") for r in pts if isinstance(r["config"].get(key), dict)), "")
        categorical = not unit and all(float(v).is_integer() for v in values)
        position = {v: i for i, v in enumerate(values)}
        log = not categorical and min(values) > 0 and max(values) / min(values) >= 8
        legend_in = 2.2  # inches beside the panels for the legend
        width = 3.8 * len(panels) + legend_in
        fig, axes = plt.subplots(len(rows), len(panels), figsize=(width, 2.9 * len(rows) + 0.4), squeeze=False)
        handles = {}
        # A line style and marker per setting of the other keys, the same in
        # every panel (so a setting reads alike across the figure and in grey).
        # (In the order swept_lines gives them: numerically by their values.)
        settings = list(dict.fromkeys(others for _, ls in panels for _, _, others, _ in ls))
        look = {o: (STYLES[i % len(STYLES)], MARKERS[i % len(MARKERS)]) for i, o in enumerate(settings)}
        for ri, (p, ys) in enumerate(rows):
            words, base_unit, value_of = PLOTS[p]
            div, shown = scale_for(base_unit, ys) if base_unit else (1, "")
            for pi, (title, ls) in enumerate(panels):
                ax = axes[ri][pi]
                for ckey, label, others, rs in ls[:20]:
                    style, marker = look[others]
                    if p == "speedup" and rs[0]["scheme"] == o["normalise"]:
                        continue  # the reference itself: the line at 1
                    pairs = [(r, value_of(r, reference_of(r, o["normalise"], index))) for r in rs]
                    pairs = [(r, v) for r, v in pairs if math.isfinite(v[0])]
                    if not pairs:
                        continue
                    xs = [position[r["swept"][key]] if categorical else r["swept"][key] for r, _ in pairs]
                    y = [v[0] / div for _, v in pairs]
                    err = [[max(0.0, v[0] / div - (v[1][0] / div if v[1] else v[0] / div)) for _, v in pairs],
                           [max(0.0, (v[1][1] / div if v[1] else v[0] / div) - v[0] / div) for _, v in pairs]]
                    name = label + (" ({})".format(others) if others else "")
                    h = ax.errorbar(xs, y, yerr=err if any(any(e) for e in err) else None, color=colour(ckey),
                                    linestyle=style, marker=marker, markersize=3.5, capsize=2, label=name)
                    handles.setdefault(name, h)
                if categorical:
                    ax.set_xticks(range(len(values)), ["{:g}".format(v) for v in values])
                else:
                    if log:
                        ax.set_xscale("log")
                    ax.set_xticks(values, [tick_label(v, unit) for v in values])
                    ax.minorticks_off()
                if ri == len(rows) - 1:
                    ax.set_xlabel(key + (" (GB/s)" if unit == "B/s" else ""))
                if pi == 0:
                    ax.set_ylabel(words.format(u=shown, ref=o["normalise"]), fontsize=8)
                if p == "speedup":
                    ax.axhline(1.0, color="grey", lw=0.8)
                ax.set_ylim(bottom=0)
                ax.grid(alpha=0.3)
                if ri == 0:
                    ax.set_title(title, fontsize=10)
            # Panels of a row compare: one y axis, unless absolute values
            # are to keep their own (scenes' frame times differ several fold).
            if p in ("speedup",) or not o["own_y"]:
                top = max(ax.get_ylim()[1] for ax in axes[ri])
                for ax in axes[ri]:
                    ax.set_ylim(0, top)
        fig.tight_layout(rect=(0, 0, 1 - legend_in / width, 1))
        # Beside the panels, not over the data; factorised where lines
        # differ in more than their colour: one entry per colour (scheme or
        # scene) and one per setting (its line style and marker, in grey).
        right = max(ax.get_position().x1 for ax in axes[0])
        colours = list(dict.fromkeys((ckey, label) for _, ls in panels for ckey, label, _, _ in ls))
        if len(settings) > 1:
            entries = [mlines.Line2D([], [], color=colour(c), lw=2) for c, _ in colours]
            names = [label for _, label in colours]
            entries += [mlines.Line2D([], [], color="black", linestyle=look[x][0], marker=look[x][1], markersize=4)
                        for x in settings]
            names += [x for x in settings]
        else:
            entries, names = list(handles.values()), list(handles.keys())
        fig.legend(entries, names, loc="center left", bbox_to_anchor=(right + 0.01, 0.5), fontsize=7, frameon=False)
        made.append((key, [p for p, _ in rows],
                     save(fig, out, "sweep-{}-{}".format(slug(sweep["name"]), slug(key)), layout=False)))
    return made


def image_figures(con, runs, out, paper_setup):
    """GPM images with a legend, and per-tile traffic with a scale: one run
    per sweep, scene, resolution and scheme (the paper's setup where the
    sweep has it, else the sweep's first point of the scheme)."""
    ids = [row[0] for row in con.execute("SELECT DISTINCT run FROM images")]
    best = {}
    for r in sorted((runs[i] for i in ids if i in runs), key=lambda r: (r["sweep"], r["position"])):
        key = (r["sweep"], r["scene"], r["resolution"], r["scheme"])
        on_paper = r["id"] in paper_setup
        if key not in best or (on_paper and not best[key][0]):
            best[key] = (on_paper, r)
    chosen = sorted((r for _, r in best.values()), key=lambda r: (r["sweep"], r["position"]))[:MAX_IMAGE_RUNS]
    made = []
    for r in chosen:
        imgs = {kind: (w, h, data, legend) for kind, w, h, data, legend in
                con.execute("SELECT kind, width, height, data, legend FROM images WHERE run = ?", (r["id"],))}
        if "gpm" not in imgs or "tile_traffic" not in imgs:
            continue
        w, h, png, legend = imgs["gpm"]
        path = os.path.join(out, "gpm-{}.png".format(r["id"]))
        with open(path, "wb") as f:
            f.write(png)
        pic = plt.imread(path)
        tw, th, data, tlegend = imgs["tile_traffic"]
        tiles = np.array(json.loads(data), dtype=float).reshape(th, tw) / 1e3
        fig, (a, b) = plt.subplots(1, 2, figsize=(11, 11 * h / w / 2 + 1.2))
        a.imshow(pic)
        a.set_axis_off()
        a.set_title("GPM that shaded each pixel", fontsize=9)
        colours = json.loads(legend)
        a.legend(handles=[mpatches.Patch(color=c, label=g) for g, c in colours.items()], fontsize=7, loc="lower right",
                 ncol=min(4, len(colours)))
        im = b.imshow(tiles, origin="lower", cmap="inferno", extent=(0, w, 0, h))
        b.set_axis_off()
        b.set_title("bytes moved between GPMs per {0}x{0} tile".format(json.loads(tlegend).get("tile_pixels", 16)),
                    fontsize=9)
        fig.colorbar(im, ax=b, fraction=0.03, label="KB per frame")
        fig.suptitle("{}: {}, {}{}".format(r["sweep"], r["scene"], r["scheme"],
                                            "".join(", {}={}".format(k, readable(r["config"].get(k))) for k in r["swept"])),
                     fontsize=10)
        os.remove(path)
        made.append((r, save(fig, out, "images-{}".format(r["id"]))))
    return made


# ---------------------------------------------------------------- page

def table(head, rows):
    out = ["<table><thead><tr>"] + ["<th>{}</th>".format(html.escape(h)) for h in head] + ["</tr></thead><tbody>"]
    for row in rows:
        out.append("<tr>" + "".join("<td>{}</td>".format(html.escape(str(c))) for c in row) + "</tr>")
    out.append("</tbody></table>")
    return "\n".join(out)


def figure(name, caption):
    # The name is a file beside the page: quoted as a URL, then escaped for
    # the attribute; the caption escaped as text.
    url = html.escape(urllib.parse.quote(name), quote=True)
    return ('<figure><a href="{0}.svg"><img src="{0}.png" alt="{1}"></a><figcaption>{1} '
            '(<a href="{0}.svg">SVG</a>)</figcaption></figure>').format(url, html.escape(caption, quote=True))


def main():
    if len(sys.argv) < 3:
        sys.exit("usage: report.py RESULTS.db OUTDIR [claims.json]")
    db, out = sys.argv[1], sys.argv[2]
    claims_path = sys.argv[3] if len(sys.argv) > 3 else os.path.join(out, "claims.json")
    with open(claims_path) as f:
        claims = json.load(f)
    ORDER[:] = claims["scheme_order"]
    COLOURS.clear()
    COLOURS.update(claims.get("scheme_colours") or {})
    options = options_of(claims)
    con, runs, sweeps = load(db)
    index = reference_index(runs.values())
    values = claim_values(claims["claims"])

    body = ["<h1>oovr report</h1>",
            "<p>{} runs ({} done, {} failed) in <code>{}</code>, from {} sweep(s); oovr {}.</p>".format(
                len(runs), sum(r["status"] == "done" for r in runs.values()),
                sum(r["status"] == "failed" for r in runs.values()), html.escape(os.path.abspath(db)), len(sweeps),
                html.escape(", ".join(sorted({"{} ({})".format(r["oovr_version"], r["git_commit"]) for r in runs.values()}))))]

    for s in sweeps:
        body.append("<h2>Sweep {}</h2>".format(html.escape(s["name"])))
        body.append("<p>{} points from <code>{}</code>; run as <code>{}</code>.</p>".format(
            s["points"], html.escape(s["file"]), html.escape(s["command"])))
        body.append("<details><summary>sweep file</summary><pre>{}</pre></details>".format(html.escape(s["definition"])))
        for key, plotted, name in swept_figures(s, runs, out, options):
            words = {"latency": "frame latency", "speedup": "speed-up over " + options["normalise"],
                     "throughput": "throughput", "traffic": "inter-GPM traffic", "energy": "memory-system energy"}
            body.append(figure(name, "{} against {}, per {} (bars: the lowest and highest of the measured frames)".format(
                ", ".join(words[p] for p in plotted), key, "scheme" if options["group"] == "scheme" else "scene")))
        mine = [r for r in runs.values() if r["sweep"] == s["name"]]
        rows = []
        for r in sorted(mine, key=lambda r: r["position"]):
            b = reference_of(r, options["normalise"], index) if r["status"] == "done" else None
            lat = metric(r, "frame", "latency")
            rows.append([r["id"], r["scene"], r["scheme"], r["resolution"]]
                        + [readable(r["config"].get(k)) for k in s["keys"]]
                        + [r["status"], "{:.3f}".format(lat * 1e3) if r["status"] == "done" else "",
                           "{:.2f}x".format(metric(b, "frame", "latency") / lat) if b and r["status"] == "done" else "",
                           "{:.1f}".format(metric(r, "frame", "throughput")) if r["status"] == "done" else "",
                           "{:.2f}".format(metric(r, "frame", "inter_gpm_bytes") / 1e6) if r["status"] == "done" else "",
                           "{:.2f}".format(metric(r, "frame", "best_to_worst")) if r["status"] == "done" else "",
                           "{:.3f}".format(metric(r, "frame", "energy") * 1e3)
                           if r["status"] == "done" and math.isfinite(metric(r, "frame", "energy")) else "",
                           r["error"]])
        body.append(table(["id", "scene", "scheme", "resolution"] + s["keys"]
                          + ["status", "latency (ms)", "speed-up over " + options["normalise"], "frames/s",
                             "inter-GPM (MB/frame)", "best/worst", "energy (mJ/frame)", "error"], rows))

    # The paper's claims after the study: those the database has runs for in
    # the open, the others (most, for a study of its own) collapsed.
    rows, unmatched = [], []
    for claim, v, per in values:
        oovr = geomean(per.values())
        (rows if per else unmatched).append(
            [claim["id"], v["label"], claim["words"] if v is claim["values"][0] else "",
             ("about " if v.get("about") else "") + form(v["paper"], v["form"]) if "paper" in v else "no number",
             form(oovr, v["form"]) if per else "no matching runs",
             "; ".join("{} {}: {}".format(g[0], g[1], form(x, v["form"])) for g, x in sorted(per.items()))])
    head = ["claim", "value", "the paper's words", "paper", "oovr (mean)", "per scene and resolution"]
    body.append("<h2>The paper's claims</h2>")
    body.append("<p>Each claim's numbers against oovr's runs that match its setup: the paper's machine "
                "(oovr's defaults, its Table 1) with only the keys the claim names changed, the run and the run it "
                "is relative to on the same scene and resolution. oovr's value is the geometric mean over the scenes "
                "and resolutions; a claim without matching runs needs another sweep "
                "(<code>experiments/paper.toml</code> runs them all). {} of {} claim values have runs here.</p>".format(
                    len(rows), len(rows) + len(unmatched)))
    if rows:
        body.append(table(head, rows))
    if unmatched:
        body.append("<details><summary>{} claim values without matching runs in this database</summary>{}</details>".format(
            len(unmatched), table(head, unmatched)))
    checks, unmeasured = [], []
    for claim in claims["claims"]:
        for k in claim["checks"]:
            on = "{} of {}".format(k["met"], k["of"]) if k["over"] != "mean" and k["verdict"] != "not measured" else ""
            (unmeasured if k["verdict"] == "not measured" else checks).append(
                [claim["id"] + (", " + k["part"] if k["part"] else ""), k["says"],
                 {"all": "every scene", "most": "most scenes", "mean": "the means"}[k["over"]], k["verdict"], on])
    check_head = ["claim", "check", "over", "oovr", "scenes it held on"]
    body.append("<p>What oovr must show to agree with each claim (<code>experiments/paper-claims.toml</code>), "
                "judged on the same runs; where the database holds several resolutions each counts as a scene.</p>")
    if checks:
        body.append(table(check_head, checks))
    if unmeasured:
        body.append("<details><summary>{} checks not measured (no matching runs)</summary>{}</details>".format(
            len(unmeasured), table(check_head, unmeasured)))
    for title, name in claim_figures(values, out):
        body.append(figure(name, title + ": oovr's value per scene and resolution (bars) and the paper's (diamonds)"))

    imgs = image_figures(con, runs, out, set(claims["paper_setup"]))
    if imgs:
        body.append("<h2>Images</h2><p>The first frame of runs stored with <code>images = true</code>, one per sweep, "
                    "scene, resolution and scheme (the paper's setup where the sweep has it; at most {}): each pixel "
                    "coloured by the GPM that shaded it, and the bytes each screen tile's work moved between "
                    "GPMs.</p>".format(MAX_IMAGE_RUNS))
        for r, name in imgs:
            body.append(figure(name, "{} {} {}".format(r["scene"], r["scheme"], r["id"])))

    style = ("body{font-family:sans-serif;max-width:1200px;margin:2em auto;color:#222}"
             "table{border-collapse:collapse;font-size:12px;margin:1em 0}"
             "th,td{border:1px solid #ccc;padding:2px 6px;text-align:left}th{background:#eee}"
             "img{max-width:100%}figure{margin:1em 0}figcaption{font-size:12px;color:#555}")
    page = ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>oovr report</title><style>{}</style></head>"
            "<body>{}</body></html>\n").format(style, "\n".join(body))
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write(page)
    print(os.path.join(out, "index.html"))


if __name__ == "__main__":
    main()
