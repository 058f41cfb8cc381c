"""oovr's Python API, behind the package: ``import oovr`` exports its public names alone."""

from __future__ import annotations

import collections.abc
import numbers
import os
import sqlite3
import threading
import urllib.parse
from typing import IO, Any, Callable, Dict, Iterable, List, Optional, Sequence, Union

from . import _oovr
from ._oovr import (
    Composer,
    Config,
    Frame,
    FrameSim,
    Record,
    Records,
    Scene,
    SchemeInput,
    SchemeResult,
    TileJob,
    Trace,
    clear_traces,
    load_scene,
    render,
    scenes,
    sort_first,
    sort_last_framebuffers,
    trace_stats,
    vertical_strip_owner,
)

# What the package exports (oovr/__init__.py: from ._api import *).
__all__ = [
    "Comparison", "Composer", "Config", "Frame", "FrameSim", "Record", "Records", "Result", "Scene", "Scheme",
    "SchemeInput", "SchemeResult", "SweepOutcome", "TileJob", "Trace", "clear_traces", "compare", "config",
    "load_scene", "read_metrics", "read_runs", "render", "scenes", "schemes", "simulate", "sort_first",
    "sort_last_framebuffers", "sweep", "trace_stats", "vertical_strip_owner",
]


def _pandas():
    try:
        import pandas
    except ImportError as e:  # pragma: no cover - pandas is installed by scripts/install-deps.sh
        raise ImportError("to_pandas needs pandas: apt-get install python3-pandas (scripts/install-deps.sh does)") from e
    return pandas


def _type(v: Any) -> str:
    return type(v).__name__


def _path(name: str, v: Any, what: str) -> str:
    """`v` as a file's path (str or os.PathLike): TypeError naming `name` for anything else."""
    if not isinstance(v, (str, os.PathLike)):
        raise TypeError(f"{name} is {what} (str or os.PathLike), not {_type(v)}")
    return os.fspath(v)


def _flag(name: str, v: Any) -> None:
    if not isinstance(v, bool):
        raise TypeError(f"{name} takes True or False, not {_type(v)}")


def _whole(name: str, v: Any, lo: Optional[int] = None, hi: Optional[int] = None) -> None:
    if not isinstance(v, numbers.Integral) or isinstance(v, bool):
        raise TypeError(f"{name} takes a whole number, not {_type(v)}")
    if lo is not None and not lo <= v <= hi:
        raise ValueError(f"{name} {v}: give a whole number from {lo} to {hi}")


def _call(name: str, *args: Any, **kwargs: Any) -> str:
    """The call as a results document's `command` records it: oovr.compare('courtyard', frames=8)."""
    words = [repr(a) for a in args] + [f"{k}={v!r}" for k, v in kwargs.items() if v is not None]
    return f"python: oovr.{name}({', '.join(words)})"


def config(preset: Optional[Union[str, os.PathLike]] = None, overrides: Optional[Dict[str, Any]] = None,
           **settings: Any) -> Config:
    """A machine configuration: `preset` (a TOML file; None: the paper's Table 1) with overrides.

    Keys are those ``oovr config --all`` lists, values as ``--set`` takes them or as Python
    numbers and booleans. Dotted keys go in `overrides` or as keyword arguments with ``__`` for
    the dot::

        oovr.config(gpms=8, link__bandwidth="32GBps")
        oovr.config("configs/ring8.toml", {"link.bandwidth": "32GBps"})

    Every key and value is checked as the CLI checks them: KeyError for an unknown key,
    ValueError for a bad value, FileNotFoundError for a missing preset.
    """
    if overrides is not None and not isinstance(overrides, collections.abc.Mapping):
        raise TypeError(f"overrides is a dict of configuration keys and values, not {_type(overrides)}")
    merged: Dict[str, Any] = dict(overrides or {})
    for k, v in settings.items():
        merged[k.replace("__", ".")] = v
    return Config(_path("preset", preset, "a TOML file's path") if preset is not None else None, merged)


def schemes() -> Dict[str, str]:
    """Every registered scheme with its description (``oovr schemes``)."""
    return _oovr.schemes()


class Scheme:
    """Base class for a distribution scheme written in Python (docs/python.md, "Schemes in Python").

    Give it a `name` and a `run(input)` that builds a FrameSim on the input, adds the frame's
    work to it (which GPM does what, in which order, and how the frame is composed) and returns
    ``sim.finish(name)``. oovr replays every memory access and runs the timing model, exactly as
    for a C++ scheme. `frames_needed(gpms)` (frames rendered at once, AFR-style) and
    `configure(config)` (machine overrides the scheme makes) are optional.
    """

    name: str = ""
    description: str = ""

    def frames_needed(self, gpms: int) -> int:
        """Frames the scheme renders at once on `gpms` GPMs (1; AFR-style schemes: one per GPM).

        A run's number of frames must be a multiple of it.
        """
        return 1

    def configure(self, config: Config) -> None:
        """Machine overrides the scheme makes before it runs (none by default).

        Called once per run with the configuration in force; set keys on `config` (for example
        ``config.set("memory.placement", "replicated")``) and they are recorded with the results.
        """

    def run(self, input: SchemeInput) -> SchemeResult:
        """The scheme itself: simulate the frame(s) of `input` and return ``sim.finish(self.name)``.

        Build ``FrameSim(input, framebuffers)``, add each GPM's work (``sim.tiles``,
        ``sim.geometry``, ``sim.transfer``, a ``Composer``), then finish. oovr checks that every
        covered fragment was rendered and every pixel reached the final frame.
        """
        raise NotImplementedError(f"{type(self).__name__}.run(input) is the scheme")


class Result:
    """One scheme's run: the fields of the JSON `runs` entry (docs/results.md) as attributes.

    ``result.frame_latency_ms``, ``result.inter_gpm_bytes``, ``result.memory["links"]``...;
    ``to_dict()`` is the JSON entry itself, ``to_pandas()`` the run's figures in long form (the
    results database's metrics rows), and ``str(result)`` what ``oovr simulate`` prints.
    """

    def __init__(self, entry: Dict[str, Any], metrics: List[tuple], text: str, images: Dict[str, Any]):
        self._entry = entry
        self._metrics = metrics
        self._text = text
        self.gpm_image = images.get("gpm")
        """With images=True: the first frame coloured by the GPM that shaded each pixel, (h, w, 4) uint8."""
        self.traffic_image = images.get("traffic")
        """With images=True: inter-GPM bytes per 16x16 tile as a heat map, (h, w, 4) uint8."""

    def __getattr__(self, name: str) -> Any:
        entry = self.__dict__.get("_entry", {})
        if name in entry:
            return entry[name]
        raise AttributeError(f"a Result has no field {name!r} (fields: {', '.join(entry)})")

    def __dir__(self) -> Iterable[str]:
        return list(super().__dir__()) + list(self._entry)

    def fields(self) -> List[str]:
        """The JSON fields, in the JSON's order."""
        return list(self._entry)

    def to_dict(self) -> Dict[str, Any]:
        """The run as the JSON's `runs` entry (a copy)."""
        import copy
        return copy.deepcopy(self._entry)

    def to_pandas(self):
        """The run's figures in long form: location, metric, value, unit (as the database's metrics)."""
        return _pandas().DataFrame(self._metrics, columns=["location", "metric", "value", "unit"])

    def __str__(self) -> str:
        return self._text.rstrip("\n")

    def __repr__(self) -> str:
        e = self._entry
        return (f"<oovr.Result {e['scheme']}: {e['frame_latency_ms']:.3f} ms, "
                f"{e['inter_gpm_bytes'] / 1e6:.2f} MB between GPMs, {e['gpms']} GPMs>")


class Comparison:
    """Several schemes on the same frames: what ``oovr compare`` prints and writes.

    ``results`` (a Result per scheme, in order), ``to_pandas()`` (the table, one row per scheme,
    the CLI's columns at full precision), ``to_dict()`` (the JSON ``oovr compare --json``
    writes), ``str(comparison)`` (the CLI's table), ``timing`` (how long traces and simulation took).
    """

    def __init__(self, native: Dict[str, Any]):
        self._document = native["document"]
        self._rows = native["rows"]
        self._text = native["compare_text"]
        self.timing: str = native["timing_text"]
        self.results: List[Result] = [
            Result(entry, metrics, text, images)
            for entry, metrics, text, images in zip(self._document["runs"], native["metrics"], native["simulate_text"],
                                                    native["images"])
        ]

    def __getitem__(self, scheme: str) -> Result:
        for r in self.results:
            if r.scheme == scheme:
                return r
        raise KeyError(f"no scheme {scheme!r} in this comparison ({', '.join(r.scheme for r in self.results)})")

    def rows(self) -> List[Dict[str, Any]]:
        """The table as dicts (NaN ratios when the baseline did not run)."""
        return [dict(r) for r in self._rows]

    def to_pandas(self):
        """The table ``oovr compare`` prints, one row per scheme (the index).

        The values are at full precision; printed, the table reads as the CLI's (latency to the
        microsecond, ratios as 1.26x, '-' where there is no baseline to divide by), and so do the
        tables made from it (a selection of rows, a sort)."""
        return _comparison_table()(self._rows).set_index("scheme")

    def metrics(self):
        """Every run's figures in long form: scheme, location, metric, value, unit."""
        pd = _pandas()
        return pd.concat([r.to_pandas().assign(scheme=r.scheme) for r in self.results], ignore_index=True)[
            ["scheme", "location", "metric", "value", "unit"]]

    def to_dict(self) -> Dict[str, Any]:
        """The results document (schema oovr.results), as ``oovr compare --json`` writes it."""
        import copy
        return copy.deepcopy(self._document)

    def to_json(self, path: Union[str, os.PathLike, IO[str]]) -> None:
        """Writes the results document as ``--json`` does: to a path (str or os.PathLike), or to an
        open text file (anything with write(); left open). A file descriptor (an int) is not
        taken: wrap it with os.fdopen and pass the file."""
        import json
        if isinstance(path, (str, bytes, os.PathLike)):
            with open(path, "w") as f:
                json.dump(self._document, f, indent=2)
                f.write("\n")
        elif not isinstance(path, (int, float)) and callable(getattr(path, "write", None)):
            json.dump(self._document, path, indent=2)
            path.write("\n")
        else:
            raise TypeError(f"to_json takes a path (str or os.PathLike) or a text file open for writing, not "
                            f"{_type(path)}" + (" (a file descriptor: pass os.fdopen(fd, 'w'))" if isinstance(path, int)
                                                 and not isinstance(path, bool) else ""))

    def __str__(self) -> str:
        return self._text.rstrip("\n")

    def __repr__(self) -> str:
        return f"<oovr.Comparison of {len(self.results)} schemes on {self._document['scene']}>"


def _scene_name(scene: Any) -> str:
    if isinstance(scene, str):
        return scene
    if isinstance(scene, Scene):
        return scene.spec
    raise TypeError(f"scene must be a name (str) or a Scene from oovr.load_scene, not {_type(scene)}")


def _run(call: str, scene, schemes_: Sequence, config_: Optional[Config], frames: Optional[int], frame: int,
         resolution: Optional[str], eye_resolution: Optional[str], aniso: int, cache: bool, images: bool,
         jobs: int) -> Comparison:
    if config_ is not None and not isinstance(config_, Config):
        raise TypeError(f"config must be an oovr.Config (oovr.config(...)), not {_type(config_)}")
    if frames is not None:
        _whole("frames", frames, 1, 1000)  # as the CLI's --frames
    _whole("frame", frame)
    if not 0 <= frame < 2**31:  # the camera path's range is checked by the C++
        raise ValueError(f"frame {frame} is out of range: frames are numbered from 0 along the camera path")
    _whole("aniso", aniso, 1, 16)
    _whole("jobs", jobs, 0, 1024)
    _flag("cache", cache)
    _flag("images", images)
    for name, v in (("resolution", resolution), ("eye_resolution", eye_resolution)):
        if v is not None and not isinstance(v, str):
            raise TypeError(f"{name} takes 'WxH' (a str), not {_type(v)}")
    return Comparison(_oovr._simulate(scene, list(schemes_), config_, frames or 0, frame, resolution, eye_resolution,
                                      aniso, cache, images, jobs, call))


def simulate(scene: Union[str, Scene], scheme: Union[str, Scheme], config: Optional[Config] = None, *,
             frames: Optional[int] = None, frame: int = 0, resolution: Optional[str] = None,
             eye_resolution: Optional[str] = None, aniso: int = 16, cache: bool = True,
             images: bool = False) -> Result:
    """Replays a scene's frames through one scheme, as ``oovr simulate``: returns a Result.

    `scheme` is a registered scheme's name or a Python Scheme (whose name must not be a
    registered scheme's). `frames` are measured from `frame` on (None: one per GPM);
    `resolution` is the whole side-by-side stereo frame (None: 1280x1024) or `eye_resolution`
    one eye's, not both; `cache=False` renders the traces again; `images=True` fills the
    result's gpm_image and traffic_image.
    """
    call = _call("simulate", _scene_name(scene),
                 scheme if isinstance(scheme, str) else getattr(scheme, "name", type(scheme).__name__),
                 frames=frames, frame=frame or None, resolution=resolution, eye_resolution=eye_resolution)
    return _run(call, scene, [scheme], config, frames, frame, resolution, eye_resolution, aniso, cache, images, 0).results[0]


def compare(scene: Union[str, Scene], schemes: Optional[Sequence[Union[str, Scheme]]] = None,
            config: Optional[Config] = None, *, frames: Optional[int] = None, frame: int = 0,
            resolution: Optional[str] = None, eye_resolution: Optional[str] = None, aniso: int = 16,
            cache: bool = True, images: bool = False, jobs: int = 0) -> Comparison:
    """Runs several schemes on the same frames, as ``oovr compare``: returns a Comparison.

    `schemes`: names and Python Schemes (None: the CLI's default, the paper's schemes in the
    paper's order); two Python schemes of one name are refused. The schemes run in parallel
    (`jobs`: at most that many at once; 0: every core); the rest as simulate().
    """
    if isinstance(schemes, str):
        raise TypeError("schemes is a list of schemes; for one, use oovr.simulate")
    if schemes is not None and (not isinstance(schemes, collections.abc.Iterable)
                                or isinstance(schemes, (bytes, collections.abc.Mapping))):
        raise TypeError(f"schemes is a list of schemes (names or Python Schemes), not {_type(schemes)}")
    names = _oovr.default_compare_schemes() if schemes is None else list(schemes)
    if not names:
        raise ValueError("schemes is empty: give at least one scheme")
    call = _call("compare", _scene_name(scene),
                 schemes=None if schemes is None else [s if isinstance(s, str) else getattr(s, "name", "") for s in names],
                 frames=frames, frame=frame or None, resolution=resolution, eye_resolution=eye_resolution)
    return _run(call, scene, names, config, frames, frame, resolution, eye_resolution, aniso, cache, images, jobs)


# How `oovr compare` prints each column (run/result_text.cpp).
_CLI_FORMAT = {
    "latency ms": "{:.3f}", "speed-up": "{:.2f}x", "frames/s": "{:.1f}", "throughput": "{:.2f}x",
    "inter-GPM MB": "{:.2f}", "traffic": "{:.2f}x", "best/worst": "{:.2f}", "energy mJ": "{:.3f}",
}
_table_class = None
_table_lock = threading.Lock()  # two threads' first tables make one class


def _comparison_table():
    """A DataFrame that prints its columns as ``oovr compare`` does (made once pandas is imported)."""
    with _table_lock:
        return _table_class or _make_comparison_table()


def _make_comparison_table():
    global _table_class
    if _table_class is None:
        pd = _pandas()

        def formatter(form):
            def f(v):
                if isinstance(v, float) and v != v:
                    return "-"
                try:
                    return form.format(v)
                except (TypeError, ValueError):
                    return str(v)
            return f

        class ComparisonTable(pd.DataFrame):
            @property
            def _constructor(self):
                return ComparisonTable

            def to_string(self, *args, **kwargs):
                if not args and "formatters" not in kwargs:
                    kwargs["formatters"] = {c: formatter(f) for c, f in _CLI_FORMAT.items() if c in self.columns}
                    kwargs.setdefault("na_rep", "-")
                return super().to_string(*args, **kwargs)

            def __repr__(self):
                return self.to_string()

        _table_class = ComparisonTable
    return _table_class


class SweepOutcome:
    """What a sweep did: points in the file, kept from the database, run, done and failed."""

    def __init__(self, d: Dict[str, Any]):
        self.name: str = d["name"]
        self.db: str = d["db"]
        self.points: int = d["points"]
        self.held: int = d["held"]
        self.run: int = d["run"]
        self.done: int = d["done"]
        self.failed: int = d["failed"]
        self.seconds: float = d["seconds"]
        self.notes: List[str] = d["notes"]

    def __repr__(self) -> str:
        return (f"<oovr.SweepOutcome {self.name!r}: {self.run} of {self.points} points run in {self.seconds:.1f} s, "
                f"{self.done} done, {self.failed} failed; {self.held} kept; {self.db}>")


def sweep(definition: Union[str, os.PathLike, Dict[str, Any]], db: Optional[Union[str, os.PathLike]] = None, *,
          resume: bool = False, retry_failed: bool = False, reconcile: bool = False, jobs: int = 0, cache: bool = True,
          progress: Union[bool, Callable[[Dict[str, Any]], None]] = True) -> SweepOutcome:
    """Runs a sweep into a results database with the engine ``oovr sweep`` uses (docs/sweeps.md).

    `definition`: a sweep file's path, or a dict with the same keys (``{"scenes": [...],
    "schemes": [...], "sweep": {"link.bandwidth": [...]}}``). `db`: the database (default: the
    file's or the sweep's name with .db, here). `resume` runs only the points the database
    lacks; `retry_failed` runs the failed ones again; `reconcile`, when the database holds this
    sweep from another version of its definition, keeps the runs the definition still has and
    deletes the others (without it that is a ValueError). `progress`: True prints a line per point,
    a function is called with each point's record (id, scene, scheme, resolution, status, error,
    wall_s, swept: the swept keys' values in base units, settings: the same as text, total: the
    points this call runs), False is quiet. A failed point is stored with its error and the sweep goes on.
    Read the database with read_runs() and read_metrics().
    """
    for flag, v in (("resume", resume), ("retry_failed", retry_failed), ("reconcile", reconcile), ("cache", cache)):
        _flag(flag, v)
    _whole("jobs", jobs, 0, 1024)
    if not isinstance(progress, bool) and not callable(progress):
        raise TypeError(f"progress takes True, False or a function of a point's record, not {_type(progress)}")
    if db is not None:
        db = _path("db", db, "the results database's path")
    if isinstance(definition, dict):
        text = _oovr._sweep_toml(definition)
        name = str(definition.get("name") or "sweep")
        base_dir = os.getcwd()
        default_db = name + ".db"
    elif isinstance(definition, (str, os.PathLike)):
        path = os.fspath(definition)
        text = _oovr._read_sweep(path)
        name = path
        base_dir = os.path.dirname(path)
        default_db = os.path.splitext(os.path.basename(path))[0] + ".db"
    else:
        raise TypeError(f"definition: a sweep definition is a sweep file's path or a dict of its keys, not "
                        f"{_type(definition)}")
    db_path = os.fspath(db) if db is not None else default_db
    count = [0]

    def print_point(r: Dict[str, Any]) -> None:
        count[0] += 1
        error = f": {r['error']}" if r["error"] else ""
        print(f"  [{count[0]}/{r['total']}] {r['status']} {r['scene']} {r['scheme']} {r['resolution']}{r['settings']} "
              f"({r['wall_s']:.1f} s){error}", flush=True)

    on_record = print_point if progress is True else (progress if callable(progress) else None)
    out = SweepOutcome(_oovr._sweep(text, name, base_dir, db_path, resume, retry_failed, reconcile, jobs, cache,
                                    _call("sweep", definition if not isinstance(definition, dict) else "<dict>",
                                          db=db_path), on_record, None))
    if progress is True:
        for n in out.notes:
            print(f"note: {n}", flush=True)
        print(f"sweep '{out.name}': {out.run} points run in {out.seconds:.1f} s: {out.done} done, {out.failed} failed; "
              f"{out.held + out.run} of {out.points} in {out.db}", flush=True)
    return out


def _open_db(path: Union[str, os.PathLike]) -> sqlite3.Connection:
    p = _path("db", path, "a results database's path")
    if not os.path.isfile(p):
        raise FileNotFoundError(f"no results database {p!r}")
    _oovr._verify_db(p)  # oovr's, whole and undamaged (ValueError naming what is not)
    # Read-only, by a URI whose path is quoted (a '?' or '#' in it is a name).
    con = sqlite3.connect("file:" + urllib.parse.quote(os.path.abspath(p)) + "?mode=ro", uri=True)
    try:
        row = con.execute("SELECT value FROM meta WHERE key = 'schema'").fetchone()
    except sqlite3.DatabaseError as e:
        con.close()
        raise ValueError(f"{p!r} is not an oovr results database: {e}") from None
    if not row or row[0] != "oovr.results.db":
        con.close()
        raise ValueError(f"{p!r} is not an oovr results database (its meta table names no oovr schema)")
    return con


def read_runs(db: Union[str, os.PathLike]):
    """A results database's runs as a DataFrame: one row per point, with its settings (a column
    per swept key, in base units), status and error, and its frame figures as columns (latency
    in s, latency_cycles, throughput, inter_gpm_bytes, best_to_worst, ... as docs/results.md
    lists them under the location 'frame')."""
    pd = _pandas()
    con = _open_db(db)
    try:
        runs = pd.read_sql_query("SELECT * FROM runs ORDER BY sweep, position", con)
        frame = pd.read_sql_query("SELECT run, metric, value FROM metrics WHERE location = 'frame'", con)
    finally:
        con.close()
    runs = runs.drop(columns=[c for c in ("config", "result", "checksum") if c in runs.columns])
    if len(frame):
        wide = frame.pivot(index="run", columns="metric", values="value")
        wide.columns.name = None
        runs = runs.merge(wide, left_on="id", right_index=True, how="left")
    return runs


def read_metrics(db: Union[str, os.PathLike]):
    """Every figure of a results database in long form, with what each run was: run, sweep,
    scene, scheme, resolution, the swept keys' columns, location, metric, value, unit."""
    pd = _pandas()
    con = _open_db(db)
    try:
        fixed = ["id", "sweep", "position", "scene", "scheme", "resolution", "frame", "frames", "aniso", "status", "error",
                 "config", "oovr_version", "git_commit", "command", "host", "started", "wall_s", "result", "checksum"]
        columns = [r[1] for r in con.execute("PRAGMA table_info(runs)")]
        swept = [c for c in columns if c not in fixed]
        select = ", ".join(["r.id AS run", "r.sweep", "r.scene", "r.scheme", "r.resolution"] +
                           ['r."' + c.replace('"', '""') + '"' for c in swept] +
                           ["m.location", "m.metric", "m.value", "m.unit"])
        return pd.read_sql_query(f"SELECT {select} FROM metrics m JOIN runs r ON r.id = m.run ORDER BY r.sweep, r.position",
                                 con)
    finally:
        con.close()
