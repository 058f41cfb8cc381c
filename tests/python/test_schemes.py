"""Schemes written in Python: the examples match their C++ twins exactly, and mistakes are
Python exceptions, never a crash."""

import importlib.util
import os

import pytest

import oovr
from conftest import ROOT


def example(name):
    spec = importlib.util.spec_from_file_location(name, os.path.join(ROOT, "examples", name + ".py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def same_but_name(a, b):
    # Less the C++ object scheme's own setting, sort_last.composition (examples/object_level.py).
    comparable = example("object_level").comparable
    da, db = comparable(a), comparable(b)
    da.pop("scheme")
    db.pop("scheme")
    return da == db


@pytest.mark.parametrize("scene, resolution, settings", [
    ("courtyard", "640x480", {}),
    ("crowd", "320x240", {"gpms": 8, "link.topology": "ring"}),
    ("courtyard", "320x240", {"composition.payload": "colour+depth", "composition.granularity": "pixel"}),
])
def test_object_level_in_python_is_the_cpp_scheme(scene, resolution, settings):
    ObjectLevel = example("object_level").ObjectLevel
    c = oovr.compare(scene, ["object", ObjectLevel()], oovr.config(overrides=settings), resolution=resolution)
    cpp, py = c.results
    assert py.scheme == "object-py"
    assert same_but_name(cpp, py)


def test_the_object_level_example_says_identical(capsys):
    assert example("object_level").main(["crowd", "--resolution", "160x128"]) == 0
    assert "identical" in capsys.readouterr().out


class SfrV(oovr.Scheme):
    """Tile SFR with vertical strips, through the shared sort-first machinery (sfr_v.cpp)."""

    name = "sfr-v-py"

    def run(self, input):
        sim = oovr.FrameSim(input)
        n, tiles_x = sim.gpms, sim.frame().tiles_x
        oovr.sort_first(sim, lambda x, y, eye: oovr.vertical_strip_owner(x, tiles_x, n), "duplicated_per_eye")
        return sim.finish(self.name)


class FastLinks(oovr.Scheme):
    """baseline-1tb's override made in Python, the work done by hand as SfrV does."""

    name = "fast-links"

    def configure(self, config):
        config.set("link.bandwidth", "1TBps")

    def run(self, input):
        return SfrV().run(input)


def test_sort_first_and_configure_match_the_cpp_schemes():
    c = oovr.compare("crowd", ["sfr-v", SfrV(), FastLinks()], resolution="320x240")
    cpp, py, fast = c.results
    assert same_but_name(cpp, py)
    assert fast.config["link.bandwidth"]["source"] == "scheme fast-links"
    assert fast.config["link.bandwidth"]["base"] == 1e12
    ref = oovr.simulate("crowd", "sfr-v", oovr.config(link__bandwidth="1TBps"), resolution="320x240")
    assert fast.frame_latency_s == ref.frame_latency_s


class Afr(oovr.Scheme):
    """AFR (afr.cpp) in Python: machine overrides, frames in flight, and latencies restated after finish()."""

    name = "afr-py"

    def configure(self, config):
        config.set("memory.placement", "replicated")

    def frames_needed(self, gpms):
        return gpms

    def run(self, input):
        n = input.gpms
        sim = oovr.FrameSim(input, n)
        records = [sim.frame(g).records_by_object() for g in range(n)]
        for o in range(input.objects):
            for g in range(n):
                f = sim.frame(g)
                left, right = records[g][o]
                sim.command(g)
                geometry = sim.geometry(g, o, 1, f.triangles_set_up(o, 0) + f.triangles_set_up(o, 1))
                both = left + right
                if len(both):
                    sim.tiles(g, both, g, [geometry])
                sim.end_draw(g)
        r = sim.finish(self.name, n)
        r.frame_latencies_s = r.gpm_busy_s
        r.frame_latency_s = sum(r.gpm_busy_s) / n
        r.throughput_fps = n / r.frame_latency_s
        r.notes = r.notes + [f"{n} frames in flight, one per GPM; every GPM holds a copy of all data"]
        return r


def test_afr_in_python_is_the_cpp_scheme():
    c = oovr.compare("crowd", ["afr", Afr()], resolution="192x128", frames=8)
    cpp, py = c.results
    assert py.frames_in_flight == 4 and len(py.frame_latencies_s) == 8
    assert py.config["memory.placement"] == {"value": "replicated", "source": "scheme afr-py"}
    cpp_d, py_d = cpp.to_dict(), py.to_dict()
    for d in (cpp_d, py_d):
        d.pop("scheme")
        d["config"]["memory.placement"].pop("source")  # "scheme afr" there, "scheme afr-py" here
    assert cpp_d == py_d
    with pytest.raises(ValueError, match="afr-py renders 4 frames at once"):
        oovr.simulate("crowd", Afr(), resolution="160x128", frames=2)


class EarliestFree(oovr.Scheme):
    """A runtime scheduler: each GPM takes the next object when its last one ends (on_finish),
    as OO-VR's distribution engine sends batches to the GPM free first."""

    name = "earliest-free"

    def run(self, input):
        sim = oovr.FrameSim(input)
        frame = sim.frame()
        queue = list(enumerate(frame.records_by_object()))
        last = {}  # unit -> GPM whose last object it ends

        def issue(g):
            if not queue:
                return
            o, (left, right) = queue.pop(0)
            sim.command(g)
            geometry = sim.geometry(g, o, 1, frame.triangles_set_up(o, 0) + frame.triangles_set_up(o, 1))
            both = left + right
            unit = sim.tiles(g, both, after=[geometry]) if len(both) else geometry
            sim.end_draw(g)
            last[unit] = g

        for g in range(sim.gpms):
            issue(g)

        def on_finish(unit):
            if unit in last:
                issue(last.pop(unit))

        self.left = queue
        return sim.finish(self.name, on_finish=on_finish)


def test_a_runtime_scheduler_adds_work_as_units_end():
    s = EarliestFree()
    a = oovr.simulate("crowd", s, resolution="192x128", frames=1)
    assert s.left == []
    b = oovr.simulate("crowd", EarliestFree(), resolution="192x128", frames=1)
    assert a.to_dict() == b.to_dict()
    every = oovr.simulate("crowd", "object", resolution="192x128", frames=1)
    assert a.covered_fragments == every.covered_fragments  # every object's tiles, once
    assert a.draws_received == every.draws_received // 2  # one draw per object here, one per view there


class FinishTwice(oovr.Scheme):
    name = "finish-twice"

    def run(self, input):
        sim = oovr.FrameSim(input)
        sim.command(0)

        def on_finish(unit):
            raise LookupError("from on_finish")

        try:
            sim.finish(self.name, on_finish=on_finish)
        except LookupError:
            pass
        return sim.finish(self.name)


def test_finish_runs_once_even_after_on_finish_raised():
    with pytest.raises(RuntimeError, match=r"finish\(\) runs once"):
        oovr.simulate("crowd", FinishTwice(), resolution="160x128", frames=1)


class Broken(oovr.Scheme):
    def __init__(self, mistake):
        self.mistake = mistake
        self.name = "broken-" + mistake

    def run(self, input):
        global kept
        sim = oovr.FrameSim(input)
        f = sim.frame()
        left = f.records_by_object()[0][0]
        if self.mistake == "gpm":
            sim.command(sim.gpms)
        elif self.mistake == "object":
            sim.geometry(0, f.objects, 1, 0)
        elif self.mistake == "unit":
            sim.geometry(0, 0, 1, 0, after=[1000])
        elif self.mistake == "framebuffer":
            sim.tiles(0, left, fb=1)
        elif self.mistake == "category":
            sim.transfer(0, 1, 10, "gossip")
        elif self.mistake == "result":
            return 42
        elif self.mistake == "raise":
            return 1 / 0
        elif self.mistake == "after_finish":
            oovr.sort_first(sim, lambda x, y, eye: 0, "shared")
            sim.finish(self.name)
            sim.command(0)
        elif self.mistake == "keep":
            kept = (sim, left, oovr.TileJob(0, left))
            oovr.sort_first(sim, lambda x, y, eye: 0, "shared")  # the frame's work, so that the run is sound
        return sim.finish(self.name)


@pytest.mark.parametrize("mistake, error, message", [
    ("gpm", ValueError, "GPM 4 does not exist"),
    ("object", ValueError, "object [0-9]+ does not exist"),
    ("unit", ValueError, "unit 1000 has not been added"),
    ("framebuffer", ValueError, "framebuffer 1 does not exist"),
    ("category", ValueError, "unknown traffic category 'gossip'"),
    ("result", TypeError, "must return what FrameSim.finish"),
    ("raise", ZeroDivisionError, "division by zero"),
    ("after_finish", RuntimeError, "no more work can be added"),
])
def test_a_mistake_in_a_python_scheme_is_an_exception(mistake, error, message):
    with pytest.raises(error, match=message):
        oovr.compare("crowd", ["baseline", Broken(mistake)], resolution="160x128", jobs=2)


class Idle(oovr.Scheme):
    """The smallest wrong scheme: it does no work, which would read as an infinite speed-up."""

    name = "idle"

    def run(self, input):
        return oovr.FrameSim(input).finish(self.name)


class Twice(oovr.Scheme):
    """Sort-first on GPM 0, every record rasterised twice (declared or not)."""

    def __init__(self, declare):
        self.declare = declare
        self.name = "twice"

    def run(self, input):
        sim = oovr.FrameSim(input)
        if self.declare:
            sim.declare_repeats(2)
        f = sim.frame()
        for o, (left, right) in enumerate(f.records_by_object()):
            sim.command(0)
            geometry = sim.geometry(0, o, 1, f.triangles_set_up(o, 0) + f.triangles_set_up(o, 1))
            both = left + right
            if len(both):
                sim.tiles(0, both, after=[geometry])
                sim.tiles(0, both, after=[geometry])
            sim.end_draw(0)
        return sim.finish(self.name)


class Uncomposed(oovr.Scheme):
    """Object-level SFR whose workers never send their pixels to the root, or send them by hand."""

    def __init__(self, by_hand):
        self.by_hand = by_hand
        self.name = "uncomposed"

    def run(self, input):
        n = input.gpms
        sim = oovr.FrameSim(input, oovr.sort_last_framebuffers(n))
        f = sim.frame()
        for o, views in enumerate(f.records_by_object()):
            g = o % n
            for eye, records in enumerate(views):
                sim.command(g)
                geometry = sim.geometry(g, o, 1, f.triangles_set_up(o, eye))
                if len(records):
                    fb = 0 if g == 0 else 1 + g  # the root draws into the final frame, workers into their own buffer
                    unit = sim.tiles(g, records, fb, [geometry])
                    if self.by_hand and g != 0:
                        sim.compose(0, 1, [unit], records=records)
                sim.end_draw(g)
        return sim.finish(self.name)


def test_a_scheme_that_breaks_a_conservation_law_is_an_error():
    with pytest.raises(ValueError, match=r"scheme 'idle' breaks a conservation law \(every covered fragment rasterised "
                                         r"once per eye\): frame 0 of the run: object [0-9]+ .* was never rasterised"):
        oovr.simulate("crowd", Idle(), resolution="160x128", frames=1)
    with pytest.raises(ValueError, match="was rasterised twice"):
        oovr.simulate("crowd", Twice(False), resolution="160x128", frames=1)
    assert oovr.simulate("crowd", Twice(True), resolution="160x128", frames=1).covered_fragments > 0
    with pytest.raises(ValueError, match=r"\(every pixel of the final frame composed once\): .* was written into private "
                                         r"framebuffer [2-4] and never composed"):
        oovr.simulate("crowd", Uncomposed(False), resolution="160x128", frames=1)
    assert oovr.simulate("crowd", Uncomposed(True), resolution="160x128", frames=1).covered_fragments > 0
    with pytest.raises(ValueError, match=r"declare_repeats\(times=0\): times must be 1 to 1000"):
        class Zero(Twice):
            def run(self, input):
                oovr.FrameSim(input).declare_repeats(0)
        oovr.simulate("crowd", Zero(True), resolution="160x128", frames=1)


def test_what_a_run_handed_out_is_dead_after_it():
    oovr.simulate("crowd", Broken("keep"), resolution="160x128", frames=1)
    sim, records, job = kept
    with pytest.raises(RuntimeError, match="scheme run that has ended"):
        sim.command(0)
    with pytest.raises(RuntimeError, match="scheme run that has ended"):
        len(records)
    with pytest.raises(RuntimeError, match="scheme run that has ended"):
        records[0].object
    # A job of an ended run given to another run's sim is refused.
    class Reuse(oovr.Scheme):
        name = "reuse"

        def run(self, input):
            sim = oovr.FrameSim(input)
            sim.tiles_together([job])
            return sim.finish(self.name)

    with pytest.raises(RuntimeError):
        oovr.simulate("crowd", Reuse(), resolution="160x128", frames=1)


def test_an_object_without_run_is_not_a_scheme():
    with pytest.raises(TypeError, match="run\\(input\\)"):
        oovr.simulate("crowd", object(), resolution="160x128")
