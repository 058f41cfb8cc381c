"""Python and the CLI give identical numbers: the same runs, the same table, the same JSON."""

import math

import oovr


def runs_without_command(doc):
    return {k: v for k, v in doc.items() if k != "command"}


def test_compare_gives_the_cli_s_results_and_table(cli_json):
    text, doc = cli_json("compare", "--scene", "courtyard", "--resolution", "640x480")
    c = oovr.compare("courtyard", resolution="640x480")
    assert runs_without_command(c.to_dict()) == runs_without_command(doc)
    assert c.to_dict()["command"].startswith("python: oovr.compare('courtyard'")
    # The printed table is the CLI's, line for line (the timing line aside).
    assert str(c).splitlines() == [l for l in text.splitlines() if not l.startswith("  time:")]
    # The DataFrame is the same table at full precision: rounded as the CLI prints, it reads the same.
    df = c.to_pandas()
    assert list(df.columns) == ["latency ms", "speed-up", "frames/s", "throughput", "inter-GPM MB", "traffic",
                                "best/worst", "energy mJ"]
    lines = {l.split()[0]: l.split()[1:] for l in text.splitlines()[2:] if l.startswith("  ") and not l.startswith("  time")}
    for scheme, row in df.iterrows():
        cols = lines[scheme]
        assert f"{row['latency ms']:.3f}" == cols[0]
        assert f"{row['speed-up']:.2f}x" == cols[1]
        assert f"{row['frames/s']:.1f}" == cols[2]
        assert f"{row['inter-GPM MB']:.2f}" == cols[4]
        assert f"{row['best/worst']:.2f}" == cols[7]
        assert f"{row['energy mJ']:.3f}" == cols[8]
    assert list(df.index) == oovr._oovr.default_compare_schemes()
    # Printed, the DataFrame shows what the CLI shows, row for row.
    printed = {l.split()[0]: l.split()[1:] for l in str(df).splitlines()[2:]}
    assert printed == {k: [w for w in v if w != "MB"] for k, v in lines.items()}


def test_simulate_gives_the_cli_s_result(cli_json):
    text, doc = cli_json("simulate", "--scene", "crowd", "--scheme", "oo-vr", "--resolution", "320x240", "--frames", "2",
                         "--set", "link.bandwidth=32GBps")
    r = oovr.simulate("crowd", "oo-vr", oovr.config(link__bandwidth="32GBps"), resolution="320x240", frames=2)
    mine = r.to_dict()
    # The override's source says where it was made: --set there, oovr.config here.
    assert mine["config"]["link.bandwidth"].pop("source") == "oovr.config"
    assert doc["runs"][0]["config"]["link.bandwidth"].pop("source") == "--set"
    assert mine == doc["runs"][0]
    assert str(r).splitlines() == [l for l in text.splitlines() if not l.startswith("  time:")]
    assert r.scheme == "oo-vr" and r.frame_latency_ms == doc["runs"][0]["frame_latency_ms"]
    m = r.to_pandas()
    lat = m[(m.location == "frame") & (m.metric == "latency")].value.item()
    assert lat == r.frame_latency_s
    assert set(m.columns) == {"location", "metric", "value", "unit"}


def test_without_the_baseline_the_ratios_are_nan_as_the_cli_prints_dashes():
    c = oovr.compare("crowd", ["sfr-v", "object"], resolution="160x128")
    assert all(math.isnan(r["speed-up"]) for r in c.rows())
    assert "        -" in str(c)
    assert str(c.to_pandas()).splitlines()[2].split()[2] == "-"


def test_a_session_renders_each_frame_once_across_configurations():
    oovr.clear_traces()
    before = oovr.trace_stats()
    for bw in ["32GBps", "64GBps", "1TBps"]:
        for gpms in [2, 4]:
            oovr.compare("crowd", ["baseline", "oo-vr"], oovr.config(gpms=gpms, link__bandwidth=bw), frames=4,
                         resolution="192x128", cache=True)
    after = oovr.trace_stats()
    rendered = after["frames_rendered"] - before["frames_rendered"]
    from_disk = after["frames_from_disk"] - before["frames_from_disk"]
    assert rendered + from_disk == 4, after
    assert after["windows_reused"] - before["windows_reused"] == 5
    assert after["scenes_loaded"] - before["scenes_loaded"] == 1
    # Another line size is another trace: rendered (or read) again.
    oovr.simulate("crowd", "baseline", oovr.config(**{"memory.line": "64B"}), frames=4, resolution="192x128")
    again = oovr.trace_stats()
    assert again["frames_rendered"] + again["frames_from_disk"] == after["frames_rendered"] + after["frames_from_disk"] + 4


def test_results_do_not_depend_on_the_schemes_run_at_once():
    one = oovr.compare("crowd", ["baseline", "object", "oo-vr"], resolution="192x128", jobs=1)
    many = oovr.compare("crowd", ["baseline", "object", "oo-vr"], resolution="192x128", jobs=3)
    assert runs_without_command(one.to_dict()) == runs_without_command(many.to_dict())


def test_images_are_the_cli_s(cli, tmp_path):
    import matplotlib.image
    import numpy as np

    r = oovr.simulate("courtyard", "object", resolution="320x240", images=True)
    cli("simulate", "--scene", "courtyard", "--scheme", "object", "--resolution", "320x240", "--gpm-image",
        str(tmp_path / "gpm.png"), "--traffic-image", str(tmp_path / "traffic.png"))
    for mine, theirs in [(r.gpm_image, "gpm.png"), (r.traffic_image, "traffic.png")]:
        png = np.rint(matplotlib.image.imread(str(tmp_path / theirs)) * 255).astype(np.uint8)
        assert mine.shape == (240, 320, 4)
        assert (mine[..., :3] == png[..., :3]).all(), theirs
    assert oovr.simulate("courtyard", "object", resolution="320x240").gpm_image is None
