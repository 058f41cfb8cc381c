"""Hostile input: wrong types, bad values, sizes past the model's bounds, several threads at once.
Every mistake is a TypeError (a wrong type) or a ValueError naming the parameter (a bad value),
never another exception, a silent default, a hang or a crash of the interpreter."""

import io
import math
import os
import re
import subprocess
import sys
import types

import pytest

import oovr

SMALL = dict(resolution="64x64", frames=1)


# ----- several threads

# Run in a fresh interpreter (the first array the module makes is the one that deadlocked) and
# with a timeout, so that a deadlock fails the test instead of hanging it.
THREADS = r"""
import threading
import oovr

frame = oovr.render("crowd", resolution="64x64")
start = threading.Barrier(8)
shapes = []

def use(i):
    start.wait()
    if i == 7:
        r = oovr.simulate("crowd", "object", resolution="64x64", frames=1, images=True)
        shapes.append(r.gpm_image.shape)
    else:
        shapes.append((frame.image if i % 2 else frame.object_id).shape)

threads = [threading.Thread(target=use, args=(i,)) for i in range(8)]
for t in threads:
    t.start()
for t in threads:
    t.join()
assert len(shapes) == 8, shapes
print("done", sorted(set(shapes)))
"""


@pytest.mark.parametrize("attempt", range(3))
def test_first_arrays_made_from_several_threads_at_once_do_not_deadlock(attempt):
    try:
        p = subprocess.run([sys.executable, "-c", THREADS], capture_output=True, text=True, timeout=60)
    except subprocess.TimeoutExpired:
        pytest.fail("eight threads making their first arrays at once deadlocked (no exit in 60 s)")
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("done [(64, 64), (64, 64, 4)]"), p.stdout


# ----- resolution and eye_resolution

@pytest.mark.parametrize("call", [
    lambda: oovr.render("crowd", resolution="64x64", eye_resolution="32x64"),
    lambda: oovr.simulate("crowd", "baseline", resolution="64x64", eye_resolution="32x64", frames=1),
    lambda: oovr.compare("crowd", ["baseline"], resolution="64x64", eye_resolution="32x64", frames=1),
])
def test_resolution_and_eye_resolution_together_are_refused(call):
    with pytest.raises(ValueError, match="give resolution or eye_resolution, not both"):
        call()


def test_either_resolution_alone_is_taken():
    assert oovr.render("crowd", eye_resolution="32x64").image.shape == (64, 64, 4)
    assert oovr.render("crowd", resolution="64x32").image.shape == (32, 64, 4)
    r = oovr.simulate("crowd", "baseline", eye_resolution="32x64", frames=1)
    assert "64x64" in str(r)


# ----- helpers' ranges

@pytest.mark.parametrize("gpms", [0, -1, 33, 2**40])
def test_sort_last_framebuffers_takes_a_machines_gpms(gpms):
    with pytest.raises(ValueError, match=r"sort_last_framebuffers\(gpms=.*1 to 32 GPMs"):
        oovr.sort_last_framebuffers(gpms)


def test_sort_last_framebuffers_counts_the_final_frame_and_one_per_gpm():
    assert [oovr.sort_last_framebuffers(n) for n in (1, 4, 32)] == [2, 5, 33]


# ----- sizes past the model's bounds

class Sized(oovr.Scheme):
    """Sort-first on GPM 0 after one call of `make(sim)`, whose result it keeps."""

    name = "sized"

    def __init__(self, make):
        self.make = make
        self.made = []

    def run(self, input):
        sim = oovr.FrameSim(input)
        self.made.append(self.make(sim))
        oovr.sort_first(sim, lambda x, y, eye: 0, "shared")
        return sim.finish(self.name)


GIB8 = 8 << 30  # the paper's machine: dram.capacity 8 GB per GPM


@pytest.mark.parametrize("make, message", [
    (lambda sim: sim.transfer(0, 1, 2**62, "composition"),
     r"transfer\(bytes=4611686018427387904\): more than one GPM's DRAM holds \(dram.capacity: 8589934592 bytes\)"),
    (lambda sim: sim.transfer(0, 1, GIB8 + 1, "composition"), r"transfer\(bytes=8589934593\)"),
    (lambda sim: sim.tiles(0, sim.frame().records(), from_gpm=1, incoming=2**62), r"tiles\(incoming=.*dram.capacity"),
    (lambda sim: sim.tiles_together([oovr.TileJob(0, sim.frame().records(), from_gpm=1, incoming=2**62)]),
     r"TileJob\(incoming=.*dram.capacity"),
    (lambda sim: sim.compose(0, 2**63), r"compose\(pixels=9223372036854775808\): more than this run's frames"),
    (lambda sim: sim.geometry(0, 0, 1, 2**62), r"geometry\(triangles=4611686018427387904\): more than object 0 has"),
    (lambda sim: sim.command(0, 2**40), r"command\(draws=1099511627776\): more than this run's frames hold"),
])
def test_sizes_past_what_the_machine_and_frames_hold_are_refused(make, message):
    with pytest.raises(ValueError, match=message):
        oovr.simulate("crowd", Sized(make), **SMALL)


def test_sizes_up_to_the_bounds_are_taken():
    moved = oovr.simulate("crowd", Sized(lambda sim: sim.transfer(0, 1, GIB8, "composition")), **SMALL)
    plain = oovr.simulate("crowd", Sized(lambda sim: -1), **SMALL)
    assert moved.inter_gpm_bytes == plain.inter_gpm_bytes + GIB8
    # The bound on pixels is what the run's records could send: every record's pixels at most.
    s = Sized(lambda sim: sum(max(r.passed, 256) for r in sim.frame().records()))
    oovr.simulate("crowd", s, **SMALL)
    most = s.made[0]
    oovr.simulate("crowd", Sized(lambda sim: sim.compose(0, most)), **SMALL)
    with pytest.raises(ValueError, match=rf"compose\(pixels={most + 1}\).*at most {most}"):
        oovr.simulate("crowd", Sized(lambda sim: sim.compose(0, most + 1)), **SMALL)


# ----- Comparison.to_json

@pytest.fixture(scope="module")
def comparison():
    return oovr.compare("crowd", ["baseline"], **SMALL)


def test_to_json_never_closes_a_descriptor_it_did_not_open(comparison):
    r, w = os.pipe()
    try:
        with pytest.raises(TypeError, match="to_json.*path.*file"):
            comparison.to_json(w)
        os.fstat(w)  # still open
        with pytest.raises(TypeError, match="to_json"):
            comparison.to_json(True)
    finally:
        os.close(r)
        os.close(w)


def test_to_json_takes_a_path_or_a_file(comparison, tmp_path):
    comparison.to_json(str(tmp_path / "a.json"))
    comparison.to_json(tmp_path / "b.json")
    out = io.StringIO()
    comparison.to_json(out)
    assert not out.closed  # the caller's file stays the caller's
    text = (tmp_path / "a.json").read_text()
    assert text == (tmp_path / "b.json").read_text() == out.getvalue()
    assert text.startswith("{") and text.endswith("}\n")
    for bad in (None, 1.5, ["a.json"], {"path": "a.json"}):
        with pytest.raises(TypeError, match="to_json"):
            comparison.to_json(bad)


# ----- Python schemes' names

class Named(oovr.Scheme):
    def __init__(self, name):
        self.name = name

    def run(self, input):
        sim = oovr.FrameSim(input)
        oovr.sort_first(sim, lambda x, y, eye: 0, "shared")
        return sim.finish(self.name)


@pytest.mark.parametrize("name", ["baseline", "oo-vr", "object"])
def test_a_python_scheme_cannot_take_a_registered_schemes_name(name):
    with pytest.raises(ValueError, match=f"'{name}'.*registered scheme"):
        oovr.compare("crowd", ["baseline", Named(name)], **SMALL)
    with pytest.raises(ValueError, match=f"'{name}'.*registered scheme"):
        oovr.simulate("crowd", Named(name), **SMALL)


def test_two_python_schemes_of_one_name_in_one_call_are_refused():
    with pytest.raises(ValueError, match="two schemes named 'mine'"):
        oovr.compare("crowd", [Named("mine"), Named("mine")], **SMALL)
    # Different names are different schemes.
    c = oovr.compare("crowd", [Named("mine"), Named("yours")], **SMALL)
    assert [r.scheme for r in c.results] == ["mine", "yours"]


class NotCounting(oovr.Scheme):
    name = "not-counting"

    def __init__(self, needed):
        self.needed = needed

    def frames_needed(self, gpms):
        return self.needed

    def run(self, input):
        return Named(self.name).run(input)


@pytest.mark.parametrize("scheme, error, message", [
    (Named(42), TypeError, "scheme's name must be a str, not int"),
    (Named(["a"]), TypeError, "scheme's name must be a str, not list"),
    (types.SimpleNamespace(name="ns", run=5), TypeError, "run.*not callable|run\\(input\\)"),
    (NotCounting("4"), TypeError, r"frames_needed\(\) must return .*int.*not str"),
    (NotCounting(None), TypeError, r"frames_needed\(\) must return .*int.*not NoneType"),
    (NotCounting(1.5), TypeError, r"frames_needed\(\) must return .*int.*not float"),
    (NotCounting(True), TypeError, r"frames_needed\(\) must return .*int.*not bool"),
    (NotCounting(0), ValueError, r"frames_needed\(\) returned 0"),
    (NotCounting(2**70), ValueError, r"frames_needed\(\) returned 1180591620717411303424"),
])
def test_a_scheme_object_of_the_wrong_shape_is_a_type_or_value_error(scheme, error, message):
    with pytest.raises(error, match=message):
        oovr.simulate("crowd", scheme, **SMALL)


# ----- every public function and constructor, fed the wrong things

NAN, INF = float("nan"), float("inf")
HOSTILE = {"None": None, "str": "x", "list": [], "dict": {}, "float": 1.5, "negative": -1, "huge": 2**62, "nan": NAN,
           "inf": INF}
OK = "ok"  # an outcome: the call is right to take the value


class From:
    """An argument made from the context of the call (a scheme's run), when the call is made."""

    def __init__(self, make):
        self.make = make


class Spec:
    """A public callable: `call(c, **args)` with the arguments `valid` (c: the context, a scheme's
    run's for those made in one); `allowed` says, per parameter and kind of value, what other than
    a TypeError or ValueError naming the parameter is right: OK (taken, or either error), or an
    exception class."""

    def __init__(self, name, call, valid, allowed=None, in_run=False, named=None):
        self.name, self.call, self.valid, self.allowed, self.in_run = name, call, valid, allowed or {}, in_run
        self.named = named or {}  # what a message names for a parameter, when not the parameter's name

    def args(self, c):
        return {k: v.make(c) if isinstance(v, From) else v for k, v in self.valid.items()}


def in_run(name, call, valid, allowed=None, named=None):
    return Spec(name, call, valid, allowed, in_run=True, named=named)


def one_run(c):
    """A sound run on the context's sim, for what needs a finished one."""
    oovr.sort_first(c.sim, lambda x, y, eye: 0, "shared")
    return c.sim.finish("hostile")


def setter(attr, value, allowed=None):
    """Setting a SchemeResult's attribute (a finished run's): its messages name the attribute."""
    def call(c, value):
        setattr(c.result, attr, value)
    return in_run("SchemeResult." + attr, call, dict(value=value), {"value": allowed or {}}, named={"value": attr})


SWEEP = {"name": "hostile", "scenes": ["crowd"], "schemes": ["baseline"], "resolution": "64x64", "frames": 1}
ABSENT = {"str": OK}  # 'x': no such file, or the database the sweep case above wrote
RECORDS = From(lambda c: c.records)
SIM = From(lambda c: c.sim)
UNIT = From(lambda c: c.sim.command(0))
JOB = From(lambda c: oovr.TileJob(0, c.records))

SPECS = [
    Spec("load_scene", lambda c, name: oovr.load_scene(name), dict(name="crowd"), {"name": {"str": ValueError}}),
    Spec("config", lambda c, **a: oovr.config(**a), dict(preset=None, overrides=None),
         {"preset": {"None": OK, "str": FileNotFoundError}, "overrides": {"None": OK, "dict": OK}}),
    Spec("config gpms", lambda c, gpms: oovr.config(gpms=gpms), dict(gpms=2)),
    Spec("Config", lambda c, **a: oovr.Config(**a), dict(preset=None, overrides={}),
         {"preset": {"None": OK, "str": FileNotFoundError}, "overrides": {"dict": OK}}),
    Spec("Config.set", lambda c, key, value: oovr.config().set(key, value), dict(key="gpms", value=2),
         {"key": {"str": KeyError}}, named={"value": "gpms"}),
    Spec("Config.get", lambda c, key: oovr.config().get(key), dict(key="gpms"), {"key": {"str": KeyError}}),
    Spec("render", lambda c, **a: oovr.render(**a),
         dict(scene="crowd", frame=0, resolution="64x64", eye_resolution=None, aniso=16, ipd_mm=64.0),
         {"resolution": {"None": OK}, "eye_resolution": {"None": OK}, "ipd_mm": {"float": OK}}),
    Spec("simulate", lambda c, **a: oovr.simulate(**a),
         dict(scene="crowd", scheme="baseline", config=None, frames=1, frame=0, resolution="64x64", eye_resolution=None,
              aniso=16, cache=True, images=False),
         {"config": {"None": OK}, "frames": {"None": OK}, "resolution": {"None": OK}, "eye_resolution": {"None": OK}}),
    Spec("compare", lambda c, **a: oovr.compare(**a),
         dict(scene="crowd", schemes=["baseline"], config=None, frames=1, frame=0, resolution="64x64",
              eye_resolution=None, aniso=16, cache=True, images=False, jobs=0),
         {"schemes": {"None": OK}, "config": {"None": OK}, "frames": {"None": OK}, "resolution": {"None": OK},
          "eye_resolution": {"None": OK}}),
    Spec("sweep", lambda c, **a: oovr.sweep(**a),
         dict(definition=SWEEP, db="hostile.db", resume=False, retry_failed=False, jobs=0, cache=True, progress=False),
         {"definition": {"str": FileNotFoundError, "dict": ValueError}, "db": {"None": OK, "str": OK}}),
    Spec("read_runs", lambda c, db: oovr.read_runs(db), dict(db=None), {"db": ABSENT}),
    Spec("read_metrics", lambda c, db: oovr.read_metrics(db), dict(db=None), {"db": ABSENT}),
    Spec("sort_last_framebuffers", lambda c, gpms: oovr.sort_last_framebuffers(gpms), dict(gpms=4)),
    Spec("vertical_strip_owner", lambda c, **a: oovr.vertical_strip_owner(**a), dict(tile_x=0, tiles_x=8, gpms=4)),
    Spec("Comparison.to_json", lambda c, path: c.comparison.to_json(path), dict(path="hostile.json"),
         {"path": {"str": OK}}),
    Spec("Comparison.__getitem__", lambda c, scheme: c.comparison[scheme], dict(scheme="baseline"),
         {"scheme": {k: KeyError for k in HOSTILE}}),
    Spec("Frame.save", lambda c, path: c.frame_image.save(path), dict(path="hostile.png"), {"path": {"str": ValueError}}),
    Spec("FrameSim outside a run", lambda c, input: oovr.FrameSim(input), dict(input=None)),
    Spec("Composer outside a run", lambda c, sim: oovr.Composer(sim, 0), dict(sim=None)),
    Spec("sort_first outside a run", lambda c, sim: oovr.sort_first(sim, lambda x, y, eye: 0, "shared"), dict(sim=None)),
    Spec("TileJob outside a run", lambda c, records: oovr.TileJob(0, records), dict(records=None)),

    in_run("FrameSim", lambda c, **a: oovr.FrameSim(**a), dict(input=From(lambda c: c.input), framebuffers=1)),
    in_run("SchemeInput.frame", lambda c, k: c.input.frame(k), dict(k=0)),
    in_run("FrameSim.frame", lambda c, k: c.sim.frame(k), dict(k=0)),
    in_run("command", lambda c, **a: c.sim.command(**a), dict(gpm=0, draws=1)),
    in_run("use_draw", lambda c, **a: c.sim.use_draw(**a), dict(gpm=0, command_unit=UNIT)),
    in_run("geometry", lambda c, **a: c.sim.geometry(**a), dict(gpm=0, object=0, vertex_passes=1, triangles=0, after=[]),
           {"after": {"list": OK}}),
    in_run("geometry_part", lambda c, **a: c.sim.geometry_part(**a),
           dict(gpm=0, object=0, begin=0.25, end=0.5, vertex_cost=0.5, triangles=0, after=[]), {"after": {"list": OK}}),
    in_run("tiles", lambda c, **a: c.sim.tiles(**a), dict(gpm=0, records=RECORDS, fb=0, after=[], from_gpm=-1, incoming=0),
           {"after": {"list": OK}, "from_gpm": {"negative": OK}}),
    in_run("tiles_together", lambda c, jobs: c.sim.tiles_together(jobs), dict(jobs=From(lambda c: [JOB.make(c)]))),
    in_run("tiles_together job", lambda c, job: c.sim.tiles_together([job]), dict(job=JOB)),
    in_run("transfer", lambda c, **a: c.sim.transfer(**a),
           dict(from_gpm=0, to_gpm=1, bytes=10, category="composition", after=[]), {"after": {"list": OK}}),
    in_run("compose", lambda c, **a: c.sim.compose(**a), dict(gpm=0, pixels=1, after=[], records=None),
           {"after": {"list": OK}, "records": {"None": OK}}),
    in_run("declare_repeats", lambda c, times: c.sim.declare_repeats(times), dict(times=2)),
    in_run("end_draw", lambda c, gpm: c.sim.end_draw(gpm), dict(gpm=0), {"gpm": {"negative": OK}}),
    in_run("work_left", lambda c, unit: c.sim.work_left(unit), dict(unit=UNIT)),
    in_run("finish", lambda c, **a: (oovr.sort_first(c.sim, lambda x, y, eye: 0, "shared"), c.sim.finish(**a)),
           dict(name="hostile", frames_in_flight=1, on_finish=None), {"name": {"str": OK}, "on_finish": {"None": OK}}),
    in_run("TileJob", lambda c, **a: c.sim.tiles_together([oovr.TileJob(**a)]),
           dict(gpm=0, records=RECORDS, fb=0, after=[], from_gpm=-1, incoming=0),
           {"after": {"list": OK}, "from_gpm": {"negative": OK}}),
    in_run("Composer", lambda c, **a: oovr.Composer(**a), dict(sim=SIM, owner=0)),
    in_run("Composer owner()", lambda c, owner: oovr.Composer(c.sim, lambda x, y: owner), dict(owner=0)),
    in_run("Composer.target", lambda c, job: oovr.Composer(c.sim, 0).target(job), dict(job=JOB)),
    in_run("Composer.send", lambda c, **a: oovr.Composer(c.sim, 0).send(**a), dict(job=JOB, unit=UNIT)),
    in_run("sort_first", lambda c, **a: oovr.sort_first(**a),
           dict(sim=SIM, owner=From(lambda c: lambda x, y, eye: 0), geometry="shared")),
    in_run("sort_first owner()", lambda c, owner: oovr.sort_first(c.sim, lambda x, y, eye: owner, "shared"),
           dict(owner=0)),
    in_run("Records.split", lambda c, **a: c.records.split(**a), dict(key=From(lambda c: lambda r: 0), parts=2)),
    in_run("Records.split key()", lambda c, key: c.records.split(lambda r: key, 2), dict(key=0)),
    in_run("Records.__getitem__", lambda c, index: c.records[index], dict(index=0),
           {"index": {"negative": OK, "huge": IndexError}}),
    in_run("Records.__add__", lambda c, other: c.records + other, dict(other=RECORDS)),
    in_run("Trace.triangles_set_up", lambda c, **a: c.frame.triangles_set_up(**a), dict(object=0, eye=0)),
    setter("frame_latency_s", 1e-3, {"float": OK, "huge": OK}),
    setter("frame_latencies_s", [1e-3]),
    setter("throughput_fps", 1e3, {"float": OK, "huge": OK}),
    setter("notes", ["a note"], {"list": OK}),
]

CASES = [(spec, param, kind) for spec in SPECS for param in spec.valid for kind in HOSTILE]


def case_id(case):
    spec, param, kind = case
    return f"{spec.name}-{param}-{kind}"


def outcome(spec, param, kind, c):
    """What the call gave: None when it returned, else the exception."""
    args = spec.args(c)
    args[param] = HOSTILE[kind]
    try:
        spec.call(c, **args)
    except Exception as e:  # noqa: BLE001 - the outcome is checked by the caller
        return e
    return None


class Battery(oovr.Scheme):
    """Runs every in-run case once, each on a FrameSim of its own, and keeps the outcomes."""

    name = "battery"

    def __init__(self, cases, comparison):
        self.cases, self.comparison, self.outcomes = cases, comparison, {}

    def context(self, input):
        sim = oovr.FrameSim(input)
        c = types.SimpleNamespace(input=input, sim=sim, frame=sim.frame(), comparison=self.comparison)
        c.records = c.frame.records()
        return c

    def run(self, input):
        for case in self.cases:
            if case_id(case) in self.outcomes:
                continue
            c = self.context(input)
            if case[0].name.startswith("SchemeResult"):
                c.result = one_run(c)
                c.sim = None
            self.outcomes[case_id(case)] = outcome(*case, c)
        c = self.context(input)
        return one_run(c)


def run_battery(comparison):
    """Every case, in a folder of its own (what a case writes, a database or a document, lands
    there); the outcome of each by its id."""
    import tempfile
    here = os.getcwd()
    with tempfile.TemporaryDirectory() as where:
        os.chdir(where)
        try:
            c = types.SimpleNamespace(comparison=comparison, frame_image=oovr.render("crowd", resolution="64x64"))
            found = {case_id(case): outcome(*case, c) for case in CASES if not case[0].in_run}
            battery = Battery([case for case in CASES if case[0].in_run], comparison)
            oovr.simulate("crowd", battery, **SMALL)
            found.update(battery.outcomes)
            return found
        finally:
            os.chdir(here)


def test_the_battery_never_crashes_the_interpreter():
    """Every case below in a child interpreter, which must finish: a crash (a null pointer
    followed, a C++ exception escaping) kills it instead of raising."""
    script = ("import oovr, test_hostile_input as t\n"
              "found = t.run_battery(oovr.compare('crowd', ['baseline'], **t.SMALL))\n"
              "print('survived', len(found))\n")
    here = os.path.dirname(os.path.abspath(__file__))
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([here, os.environ.get("PYTHONPATH", "")]))
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300, env=env)
    assert p.returncode == 0 and f"survived {len(CASES)}" in p.stdout, f"exit {p.returncode}: {p.stderr[-2000:]}"


@pytest.fixture(scope="module")
def outcomes(comparison):
    return run_battery(comparison)


@pytest.mark.parametrize("case", CASES, ids=case_id)
def test_a_wrong_argument_is_a_type_or_value_error_naming_it(case, outcomes):
    spec, param, kind = case
    got = outcomes[case_id(case)]
    allowed = spec.allowed.get(param, {}).get(kind)
    if allowed is OK:
        assert got is None or isinstance(got, (TypeError, ValueError)), repr(got)
        return
    if allowed is not None:
        assert isinstance(got, allowed), f"{spec.name}({param}={HOSTILE[kind]!r}) gave {got!r}, not {allowed}"
        return
    assert got is not None, f"{spec.name}({param}={HOSTILE[kind]!r}) was taken"
    assert type(got) in (TypeError, ValueError), f"{spec.name}({param}={HOSTILE[kind]!r}) raised {got!r}"
    name = spec.named.get(param, param)
    assert re.search(re.escape(name), str(got), re.IGNORECASE), (
        f"{spec.name}({param}={HOSTILE[kind]!r}): {type(got).__name__} does not name {name!r}: {got}")


def test_finite_numbers_are_needed_where_a_number_is_finite():
    for bad in (NAN, INF, -INF):
        with pytest.raises(ValueError, match="ipd_mm"):
            oovr.render("crowd", resolution="64x64", ipd_mm=bad)
        with pytest.raises(ValueError, match="not finite"):
            oovr.config(**{"gpm.draw_cycles": bad})
    assert math.isfinite(oovr.render("crowd", resolution="64x64", ipd_mm=0.0).summary["layers_per_pixel_drawn"])
