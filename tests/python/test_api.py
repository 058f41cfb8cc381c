"""The module's surface: scenes, configurations, rendering, the errors it raises, and its stubs."""

import ast
import json
import os

import numpy as np
import pytest

import oovr
from conftest import ROOT


def test_version_and_registries_are_the_clis(cli):
    assert cli("--version").strip() == f"oovr {oovr.__version__} (commit {oovr.git_commit})"
    listed = [line.split()[0] for line in cli("schemes").splitlines()[1:] if line.strip()]
    assert list(oovr.schemes()) == listed
    names = {s["name"] for s in oovr.scenes()}
    assert {"courtyard", "crowd"} <= names
    assert all(set(s) == {"name", "kind", "description"} for s in oovr.scenes())


def test_a_scene_has_the_figures_scene_info_prints(cli):
    s = oovr.load_scene("crowd")
    info = json.loads(cli("scene-info", "--scene", "crowd", "--json"))
    assert s.info() == info
    assert (s.name, s.draws, s.triangles, s.textures, s.max_sharing) == (
        info["scene"], info["draws"], info["triangles"], info["textures"], info["max_objects_sharing_a_texture"])
    assert {str(k): v for k, v in s.sharing.items()} == info["sharing_histogram"]
    assert oovr.load_scene("crowd").spec == "crowd"
    assert "crowd" in repr(s)


def test_a_configuration_is_checked_as_the_cli_checks_it():
    c = oovr.config(gpms=8, link__bandwidth="32GBps", overrides={"gpm.draw_cycles": 0.5})
    assert c["gpms"] == "8" and c.get("link.bandwidth") == "32 GB/s"
    e = c.entries()["link.bandwidth"]
    assert (e["base"], e["unit"], e["source"]) == (32e9, "B/s", "oovr.config")
    assert c.entries()["memory.line"]["source"] == "default"
    assert "gpms" in c and "no.such.key" not in c
    assert len(c.keys()) == len(c.entries()) > 40
    with pytest.raises(KeyError, match="unknown configuration key 'link.bandwdith'"):
        oovr.config(link__bandwdith="32GBps")
    with pytest.raises(ValueError, match="'gpms'.*whole number"):
        oovr.config(gpms="many")
    with pytest.raises(ValueError, match="gpms"):
        oovr.config(gpms=0)
    with pytest.raises(FileNotFoundError, match="no/such.toml"):
        oovr.config("/no/such.toml")
    with pytest.raises(TypeError, match="configuration key 'gpms'"):
        oovr.config(gpms=[8])
    with pytest.raises(ValueError, match="not finite"):
        oovr.config(**{"gpm.draw_cycles": float("nan")})
    # A bad set() leaves the configuration as it was.
    with pytest.raises(ValueError):
        c.set("gpms", -3)
    assert c["gpms"] == "8"
    d = c.copy()
    d.set("gpms", 2)
    assert (c["gpms"], d["gpms"]) == ("8", "2")
    assert "gpms = 8" in c.to_toml()
    assert repr(oovr.config()) == "<oovr.Config: the paper's Table 1>"


def test_a_preset_reads_as_the_cli_reads_it(cli):
    preset = os.path.join(ROOT, "configs", "ring-8.toml")
    c = oovr.config(preset, link__bandwidth="128GBps")
    printed = cli("config", "--config", preset, "--set", "link.bandwidth=128GBps")
    assert c.to_toml() == "".join(printed.splitlines(keepends=True)[1:])


def test_a_rendered_frame_is_the_image_and_figures_the_cli_gives(cli, tmp_path):
    f = oovr.render("crowd", frame=3, resolution="320x240")
    assert f.image.shape == (240, 320, 4) and f.image.dtype == np.uint8
    assert f.object_id.shape == (240, 320) and f.object_id.dtype == np.uint32
    assert (f.image[..., 3] == 255).all()
    s = f.summary
    out = cli("render", "--scene", "crowd", "--frame", "3", "--resolution", "320x240", "--out", str(tmp_path / "c.png"))
    assert f"fragments covered {s['fragments_covered']}, shaded {s['fragments_shaded']}, passed {s['fragments_passed']}" in out
    assert f"trace: {s['records']} (object, eye, tile) records, {s['texture_line_reads']} texture line reads" in out
    f.save(str(tmp_path / "p.png"))
    assert (tmp_path / "p.png").read_bytes() == (tmp_path / "c.png").read_bytes()
    # The array's first row is the image's top row: drawn pixels have an object id.
    drawn = f.object_id != 0xFFFFFFFF
    assert drawn.sum() == s["pixels_drawn"]


@pytest.mark.parametrize("call, error, message", [
    (lambda: oovr.load_scene("no-such-scene"), ValueError, "unknown scene 'no-such-scene'"),
    (lambda: oovr.load_scene("/no/such/model.obj"), FileNotFoundError, "no such file"),
    (lambda: oovr.load_scene(""), ValueError, "no scene given"),
    (lambda: oovr.render("crowd", frame=100000), ValueError, "out of range"),
    (lambda: oovr.render("crowd", resolution="641x480"), ValueError, "641x480"),
    (lambda: oovr.render("crowd", aniso=0), ValueError, "anisotrop"),
    (lambda: oovr.render(42), TypeError, "scene must be a name"),
    (lambda: oovr.simulate("crowd", "no-such-scheme"), ValueError, "unknown scheme 'no-such-scheme'"),
    (lambda: oovr.simulate("crowd", 3), TypeError, "registered scheme's name"),
    (lambda: oovr.simulate("crowd", "baseline", {"gpms": 2}), TypeError, "oovr.Config"),
    (lambda: oovr.simulate("crowd", "baseline", frames=0), ValueError, "frames"),
    (lambda: oovr.simulate("crowd", "baseline", frames=10**9), ValueError, "frames 1000000000: .* 1 to 1000"),
    (lambda: oovr.simulate("crowd", "baseline", frames=2.5), TypeError, "frames takes a whole number"),
    (lambda: oovr.simulate("crowd", "baseline", resolution=12), TypeError, "resolution takes 'WxH'"),
    (lambda: oovr.compare("crowd", ["baseline"], jobs=-1), ValueError, "jobs -1"),
    (lambda: oovr.render("crowd", resolution="0x0"), ValueError, "bad resolution '0x0'"),
    (lambda: oovr.config(gpms=10**30), ValueError, "'gpms'.*from 1 to 32"),
    (lambda: oovr.config(gpms=None), TypeError, "takes a str, int, float or bool"),
    (lambda: oovr.config("/"), ValueError, "is a directory"),
    (lambda: oovr.simulate("crowd", "baseline", frame=-1), ValueError, "out of range"),
    (lambda: oovr.compare("crowd", ["afr"], frames=3, resolution="64x64"), ValueError,
     "frames 3: afr renders 4 frames at once"),
    (lambda: oovr.compare("crowd", "baseline"), TypeError, "list of schemes"),
    (lambda: oovr.read_runs("/no/such.db"), FileNotFoundError, "no results database"),
])
def test_bad_arguments_raise_with_oovrs_message(call, error, message):
    with pytest.raises(error, match=message):
        call()


@pytest.mark.parametrize("variable, scene", [("OOVR_OPENARENA_DIR", "oa:oa_dm4"), ("OOVR_NEXUIZ_DIR", "nexuiz:strength")])
def test_game_data_that_is_not_installed_is_file_not_found(tmp_path, monkeypatch, variable, scene):
    # What a script leaves out when a game is not installed (examples/link_bandwidth.py).
    monkeypatch.setenv(variable, str(tmp_path / "none"))
    with pytest.raises(FileNotFoundError, match="game directory .*none' does not exist"):
        oovr.load_scene(scene)
    monkeypatch.setenv(variable, str(tmp_path))
    with pytest.raises(FileNotFoundError, match="holds no .pk3 archives"):
        oovr.load_scene(scene)


def test_a_file_that_is_not_a_results_database_is_refused(tmp_path):
    p = tmp_path / "x.db"
    p.write_text("not sqlite")
    with pytest.raises(ValueError, match="not an oovr results database"):
        oovr.read_runs(p)


def test_the_stubs_declare_exactly_the_public_names():
    stub = os.path.join(os.path.dirname(oovr.__file__), "__init__.pyi")
    tree = ast.parse(open(stub).read())
    declared = set()
    for node in tree.body:
        if isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            declared.add(node.name)
        elif isinstance(node, ast.AnnAssign):
            declared.add(node.target.id)
    public = set(oovr.__all__) | {"__version__"}
    assert declared == public
    assert all(hasattr(oovr, n) for n in public)
    # Every public function and class says what it does.
    for n in oovr.__all__:
        obj = getattr(oovr, n)
        if callable(obj):
            assert (obj.__doc__ or "").strip(), n
    # What a scheme written in Python overrides says what it is for.
    for m in ("run", "configure", "frames_needed"):
        assert (getattr(oovr.Scheme, m).__doc__ or "").strip(), m


def test_the_package_exports_its_public_names_alone():
    # No module or typing name it uses leaks out (oovr.os, oovr.sqlite3, oovr.Any).
    exported = {n for n in vars(oovr) if not n.startswith("_")}
    assert exported == set(oovr.__all__), sorted(exported - set(oovr.__all__))
    for leaked in ("os", "sqlite3", "threading", "numbers", "Any", "Optional", "annotations"):
        assert not hasattr(oovr, leaked), leaked
    assert oovr.Scheme.__module__ == "oovr" and oovr.compare.__module__ == "oovr"
