"""The report's study plots (src/oovr/experiments/report.py, swept_figures):
one colour per scheme in every figure, lines only through runs that differ
in the plotted key, numbers in numeric order, values labelled as people
write them, and each figure as PNG, SVG and PDF."""
import importlib.util
import os

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
SPEC = importlib.util.spec_from_file_location("report", os.path.join(HERE, "..", "..", "src", "oovr", "experiments", "report.py"))
report = importlib.util.module_from_spec(SPEC)
SPEC.loader.exec_module(report)


def run(scheme, bw, latency, extra=None, swept=True, scene="s", frames=(1.0,)):
    config = {"link.bandwidth": {"value": str(bw), "base": bw, "unit": "B/s"}}
    for k, v in (extra or {}).items():
        config[k] = {"value": str(v), "base": v}
    return {"id": "{:016x}".format(abs(hash((scheme, bw, latency, str(extra), swept))) % (1 << 64)), "sweep": "t",
            "status": "done", "scene": scene, "resolution": "64x32", "scheme": scheme, "config": config,
            "swept": {"link.bandwidth": bw} if swept else {},
            "m": {("frame", "latency"): (latency, "s"), ("frame", "inter_gpm_bytes"): (1e6, "B")},
            "result": {"frame_latencies_s": [latency * f for f in frames]}}


@pytest.fixture(autouse=True)
def order():
    report.ORDER[:] = ["baseline", "oo-vr"]


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
    assert [k for k, _ in made] == ["link.bandwidth"]
    for ext in ("png", "svg", "pdf"):
        f = tmp_path / (made[0][1] + "." + ext)
        assert f.exists() and f.stat().st_size > 1000, ext
