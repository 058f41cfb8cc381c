"""The report's study plots (src/oovr/experiments/report.py, swept_figures):
one colour per scheme in every figure, lines only through runs that differ
in the plotted key, numbers in numeric order, values labelled as people
write them, speed-ups over the chosen scheme's run of the same setup,
shared y axes, the rows and grouping asked for, and each figure as PNG,
SVG and PDF."""
import importlib.util
import os

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
SPEC = importlib.util.spec_from_file_location("report", os.path.join(HERE, "..", "..", "src", "oovr", "experiments", "report.py"))
report = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(report)


POSITION = [0]


def run(scheme, bw, latency, extra=None, swept=True, scene="s", frames=(1.0,), energy=None):
    config = {"link.bandwidth": {"value": str(bw), "base": bw, "unit": "B/s"}}
    for k, v in (extra or {}).items():
        config[k] = {"value": str(v), "base": v}
    POSITION[0] += 1
    m = {("frame", "latency"): (latency, "s"), ("frame", "inter_gpm_bytes"): (1e6, "B")}
    if energy is not None:
        m[("frame", "energy")] = (energy, "J")
    return {"id": "{:016x}".format(abs(hash((scheme, bw, latency, str(extra), swept, scene))) % (1 << 64)), "sweep": "t",
            "position": POSITION[0], "status": "done", "scene": scene, "resolution": "64x32", "scheme": scheme,
            "frame": 0, "aniso": 16, "config": config, "swept": {"link.bandwidth": bw} if swept else {},
            "m": m, "result": {"frame_latencies_s": [latency * f for f in frames]}}


@pytest.fixture(autouse=True)
def order():
    report.ORDER[:] = ["baseline", "oo-vr"]


def test_oovr_gives_the_colours_its_paper_charts_use():
    report.COLOURS.update({"oo-vr": "#9467bd"})
    try:
        assert report.scheme_colour("oo-vr") == "#9467bd"
    finally:
        report.COLOURS.clear()
    # Without oovr's, the same palette: tab20's dark shades first.
    import matplotlib.colors
    assert matplotlib.colors.to_hex(report.PALETTE[0]) == "#1f77b4"
    assert matplotlib.colors.to_hex(report.PALETTE[10]) == "#aec7e8"


def test_a_scheme_keeps_its_colour_and_schemes_differ():
    assert report.scheme_colour("oo-vr") == report.scheme_colour("oo-vr")
    colours = [report.scheme_colour(s) for s in ("baseline", "oo-vr")]
    assert colours[0] != colours[1]
    assert report.scheme_colour("someone-elses") == report.scheme_colour("someone-elses")


def test_lines_join_only_runs_differing_in_the_plotted_key():
    runs = [run("baseline", 128e9, 2.0), run("baseline", 32e9, 3.0), run("baseline", 1e12, 1.0),
            # An ablation: another line, not a zigzag through the baseline's.
            run("baseline", 32e9, 5.0, {"oo.split": 0}), run("baseline", 128e9, 4.0, {"oo.split": 0}),
            run("oo-vr", 32e9, 2.5)]
    lines = report.swept_lines(runs, "link.bandwidth")
    assert [(s, len(rs)) for s, _, rs in lines] == [("baseline", 2), ("baseline", 3), ("oo-vr", 1)] or \
        [(s, len(rs)) for s, _, rs in lines] == [("baseline", 3), ("baseline", 2), ("oo-vr", 1)]
    for scheme, others, rs in lines:
        xs = [r["swept"]["link.bandwidth"] for r in rs]
        assert xs == sorted(xs), "numeric order: 32 before 128 before 1000"
        if scheme == "baseline":
            assert others.startswith("oo.split=")
    # The main grid's run at the default joins the line whose other keys it shares.
    grid = run("baseline", 64e9, 2.2, swept=False)
    lines = report.swept_lines(runs, "link.bandwidth", [grid])
    full = [rs for s, o, rs in lines if s == "baseline" and len(rs) == 4]
    assert full and [r["swept"]["link.bandwidth"] for r in full[0]] == [32e9, 64e9, 128e9, 1e12]


def test_values_read_as_people_write_them():
    assert [report.tick_label(v, "B/s") for v in (32e9, 64e9, 512e9, 1e12)] == ["32", "64", "512", "1 TB/s"]
    assert report.tick_label(8, "") == "8"
    assert sorted([128e9, 32e9, "x", 64e9], key=report.numeric)[:3] == [32e9, 64e9, 128e9]


def test_a_figure_is_written_as_png_svg_and_pdf(tmp_path):
    runs = {r["id"]: r for r in [run("baseline", v, 1.0 + 1e9 / v, frames=(0.9, 1.1)) for v in (32e9, 128e9, 1e12)] +
            [run("oo-vr", v, 0.5 + 1e9 / v) for v in (32e9, 128e9, 1e12)]}
    made = report.swept_figures({"name": "t", "keys": ["link.bandwidth"]}, runs, str(tmp_path))
    # The default rows this database can fill: no energy was stored.
    assert [(k, p) for k, p, _ in made] == [("link.bandwidth", ["latency", "speedup", "traffic"])]
    for ext in ("png", "svg", "pdf"):
        f = tmp_path / (made[0][2] + "." + ext)
        assert f.exists() and f.stat().st_size > 1000, ext


def test_a_speedup_is_over_the_chosen_schemes_run_of_the_same_setup():
    runs = [run("baseline", 32e9, 4.0, frames=(0.5, 1.5)), run("baseline", 32e9, 1.0, {"oo.split": 0}),
            run("oo-vr", 32e9, 2.0, {"oo.batch_queue": 4}, frames=(1.0, 1.0)), run("oo-vr", 32e9, 8.0, scene="other")]
    index = report.reference_index(runs)
    # OO-VR's own key is no difference; the ablated baseline's is.
    assert report.reference_of(runs[2], "baseline", index) is runs[0]
    assert report.reference_of(runs[0], "baseline", index) is runs[0]
    assert report.reference_of(runs[3], "baseline", index) is None, "another scene has no baseline"
    y, spread = report.PLOTS["speedup"][2](runs[2], runs[0])
    assert y == 2.0
    assert spread == (1.0, 3.0), "frame by frame: 2/2 and 6/2"
    assert report.PLOTS["speedup"][2](runs[3], None)[0] != report.PLOTS["speedup"][2](runs[3], None)[0]  # NaN
    assert report.PLOTS["latency"][2](runs[0], None) == (4.0, (2.0, 6.0))


def test_rows_panels_and_axes_follow_the_options(tmp_path, monkeypatch):
    runs = {r["id"]: r for r in
            [run("baseline", v, 1.0 + 1e9 / v, scene=sc, energy=2e-3) for v in (32e9, 128e9) for sc in ("a", "b")] +
            [run("oo-vr", v, 0.5 + 1e9 / v, scene=sc, energy=1e-3) for v in (32e9, 128e9) for sc in ("a", "b")]}
    figures = []
    real_subplots = report.plt.subplots

    def subplots(*args, **kwargs):
        fig, axes = real_subplots(*args, **kwargs)
        figures.append(axes)
        return fig, axes

    monkeypatch.setattr(report.plt, "subplots", subplots)
    sweep = {"name": "t", "keys": ["link.bandwidth"]}
    made = report.swept_figures(sweep, runs, str(tmp_path))
    assert made[0][1] == ["latency", "speedup", "traffic", "energy"]
    axes = figures[-1]
    assert axes.shape == (4, 2), "a row per plot, a panel per scene"
    for row in axes:
        assert len({ax.get_ylim() for ax in row}) == 1, "each row's panels share their y axis"
    assert [ax.get_title() for ax in axes[0]] == ["a, 64x32", "b, 64x32"]
    # Both schemes' latencies; the speed-ups of OO-VR only (the baseline's own is the line at 1).
    assert [len(axes[0][0].containers), len(axes[1][0].containers)] == [2, 1]
    # Grouped by scheme, with two rows asked for and their own y axes.
    opts = report.options_of({"options": {"plots": ["energy", "speedup"], "group": "scheme", "own_y": True}})
    made = report.swept_figures(sweep, runs, str(tmp_path), opts)
    axes = figures[-1]
    assert made[0][1] == ["energy", "speedup"] and axes.shape == (2, 2)
    assert [ax.get_title() for ax in axes[0]] == ["baseline", "oo-vr"]
    assert axes[0][0].get_ylim() != axes[0][1].get_ylim(), "absolute rows keep their own axes with own_y"
    assert axes[1][0].get_ylim() == axes[1][1].get_ylim(), "speed-ups always share theirs"
    assert "mJ" in axes[0][0].get_ylabel()
    # Only the keys asked for are drawn.
    assert report.swept_figures(sweep, runs, str(tmp_path), report.options_of({"options": {"x": ["gpms"]}})) == []
    with pytest.raises(SystemExit):
        report.options_of({"options": {"plots": ["joules"]}})
