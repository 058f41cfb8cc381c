"""oovr from Python: stereo VR rendering on NUMA multi-GPU systems (OO-VR, ISCA 2019).

The same library as the ``oovr`` command, in the interpreter: load scenes, render frames,
simulate and compare schemes, run sweeps into a results database and read it back as
DataFrames, and write distribution schemes in Python that oovr's memory system and timing
model replay. docs/python.md is the guide.

Scenes and traces stay in memory for the interpreter's life (and the on-disk trace cache
serves what other processes rendered), so a loop over configurations renders each frame once;
``trace_stats()`` says what was rendered and what was reused.

Errors carry oovr's message: ``FileNotFoundError`` for a file or game data that is not there,
``KeyError`` for an unknown configuration key, ``ValueError`` for any other bad argument (naming
it), ``TypeError`` for an argument of the wrong type.
"""

from . import _api, _oovr
from ._api import *  # noqa: F401,F403 - the public names, _api.__all__

__version__: str = _oovr.version()
git_commit: str = _oovr.git_commit()

__all__ = sorted(_api.__all__ + ["git_commit"])

# The Python-defined names read as the package's (help(), reprs, tracebacks).
for _name in ("Comparison", "Result", "Scheme", "SweepOutcome", "compare", "config", "read_metrics", "read_runs",
              "schemes", "simulate", "sweep"):
    globals()[_name].__module__ = __name__
del _name
