"""oovr.sweep is the engine `oovr sweep` uses: a dict or a file gives the database the CLI gives,
and read_runs / read_metrics read it into DataFrames."""

import os
import sqlite3

import pytest

import oovr

SWEEP = {
    "name": "parity",
    "scenes": ["crowd"],
    "schemes": ["baseline", "object"],
    "resolutions": ["192x128"],
    "frames": 4,
    "images": True,
    "sweep": {"link.bandwidth": ["32GBps", "1TBps"], "gpms": [2, 4]},
}
TOML = """name = "parity"
scenes = ["crowd"]
schemes = ["baseline", "object"]
resolutions = ["192x128"]
frames = 4
images = true
[sweep]
"link.bandwidth" = ["32GBps", "1TBps"]
gpms = [2, 4]
"""


def dump(path):
    """What two databases of one sweep agree on (tests/cli/dump_runs.sh): not when, where or by which command."""
    con = sqlite3.connect(path)
    try:
        # The swept columns must exist: SQLite reads a double-quoted name that is no column as a string.
        columns = {row[1] for row in con.execute("PRAGMA table_info(runs)")}
        assert {"link.bandwidth", "gpms"} <= columns, columns
        runs = con.execute('SELECT id, sweep, position, scene, scheme, resolution, frame, frames, aniso, config, status, '
                           'error, oovr_version, git_commit, result, "link.bandwidth", gpms FROM runs ORDER BY id').fetchall()
        metrics = con.execute("SELECT * FROM metrics ORDER BY run, location, metric").fetchall()
        images = con.execute("SELECT run, kind, width, height, data, legend FROM images ORDER BY run, kind").fetchall()
    finally:
        con.close()
    return runs, metrics, images


def test_a_dict_sweep_gives_the_database_the_cli_gives(cli, tmp_path, capsys):
    (tmp_path / "parity.toml").write_text(TOML)
    cli("sweep", str(tmp_path / "parity.toml"), "--db", str(tmp_path / "cli.db"))
    out = oovr.sweep(SWEEP, tmp_path / "py.db", jobs=2)
    assert (out.points, out.run, out.done, out.failed, out.held) == (8, 8, 8, 0, 0)
    printed = capsys.readouterr().out
    assert printed.count(" done crowd ") == 8 and "sweep 'parity': 8 points run" in printed
    assert dump(tmp_path / "cli.db") == dump(tmp_path / "py.db")
    # A file gives the same database too, quietly when asked.
    seen = []
    oovr.sweep(tmp_path / "parity.toml", tmp_path / "file.db", progress=seen.append)
    assert len(seen) == 8 and {r["status"] for r in seen} == {"done"}
    assert dump(tmp_path / "file.db") == dump(tmp_path / "cli.db")


def test_runs_and_metrics_read_into_dataframes(tmp_path):
    oovr.sweep(SWEEP, tmp_path / "r.db", progress=False)
    runs = oovr.read_runs(tmp_path / "r.db")
    assert len(runs) == 8
    assert {"id", "scene", "scheme", "status", "link.bandwidth", "gpms", "latency", "inter_gpm_bytes"} <= set(runs.columns)
    assert sorted(runs["link.bandwidth"].unique()) == [32e9, 1e12]
    assert "config" not in runs.columns and "result" not in runs.columns
    r = oovr.simulate("crowd", "object", oovr.config(link__bandwidth="32GBps", gpms=2), resolution="192x128", frames=4)
    row = runs[(runs.scheme == "object") & (runs["link.bandwidth"] == 32e9) & (runs.gpms == 2)]
    assert row.latency.item() == r.frame_latency_s
    m = oovr.read_metrics(tmp_path / "r.db")
    assert {"run", "scene", "scheme", "link.bandwidth", "gpms", "location", "metric", "value", "unit"} <= set(m.columns)
    assert set(m.run) == set(runs.id)
    links = m[m.location.str.startswith("link[")]
    assert len(links) > 0


def test_a_sweep_resumes_and_refuses_to_run_into_a_database_twice(tmp_path):
    small = dict(SWEEP, sweep={"link.bandwidth": ["32GBps"]}, images=False)
    oovr.sweep(small, tmp_path / "s.db", progress=False)
    with pytest.raises(ValueError, match="holds 2 of this sweep's 2 points already: give --resume"):
        oovr.sweep(small, tmp_path / "s.db", progress=False)
    more = dict(small, sweep={"link.bandwidth": ["32GBps", "64GBps"]})
    # The same sweep, edited: reconciled only when asked to.
    with pytest.raises(ValueError, match="defined otherwise .* give --reconcile to keep the 2 and delete the 0"):
        oovr.sweep(more, tmp_path / "s.db", resume=True, progress=False)
    out = oovr.sweep(more, tmp_path / "s.db", resume=True, reconcile=True, progress=False)
    assert (out.held, out.run, out.done) == (2, 2, 2)
    assert len(oovr.read_runs(tmp_path / "s.db")) == 4


def test_a_failed_point_is_stored_and_the_sweep_goes_on(tmp_path):
    out = oovr.sweep(dict(SWEEP, scenes=["crowd", "/no/such/model.obj"], images=False, sweep={}), tmp_path / "f.db",
                     progress=False)
    assert (out.done, out.failed) == (2, 2)
    runs = oovr.read_runs(tmp_path / "f.db")
    assert set(runs[runs.status == "failed"].error.str.contains("no such file")) == {True}


@pytest.mark.parametrize("definition, error, message", [
    ({"scenes": ["crowd"]}, ValueError, "no points"),
    ({"scenes": ["crowd"], "schemes": ["baseline"], "colour": "blue"}, ValueError, "colour"),
    ({"scenes": ["crowd"], "schemes": ["baseline"], "set": {"no.such.key": 1}}, KeyError, "no.such.key"),
    ({"scenes": ["crowd"], "schemes": ["baseline"], "frames": None}, ValueError, "null"),
    ({"scenes": ["crowd"], "schemes": ["baseline"], "set": {"gpm.draw_cycles": float("nan")}}, ValueError, "NaN"),
    ({"scenes": ["crowd"], "schemes": ["baseline"], "sweep": {"gpms": list(range(1, 33)),
      "link.bandwidth": [f"{i}GBps" for i in range(1, 5000)]}}, ValueError, "more than 100000 points"),
    ([1, 2], TypeError, "a sweep file's path or a dict"),
    ("/no/such/sweep.toml", FileNotFoundError, "no/such/sweep.toml"),
])
def test_bad_sweeps_are_refused_before_anything_runs(tmp_path, definition, error, message):
    with pytest.raises(error, match=message):
        oovr.sweep(definition, tmp_path / "bad.db", progress=False)
    assert not os.path.exists(tmp_path / "bad.db") or len(oovr.read_runs(tmp_path / "bad.db")) == 0
