#!/bin/sh
# Runs one file of the Python module's tests with Debian's python3 and pytest
# (docs/python.md), or reports "skipped" (exit 77) with the reason when the
# module was not built or pytest is not installed.
# Usage: run.sh BUILD/python TEST_FILE [pytest arguments]
set -u
pydir=$1
shift
if ! ls "$pydir"/oovr/_oovr*.so >/dev/null 2>&1; then
  echo "skipped: the oovr Python module was not built (pybind11-dev or python3-dev missing: scripts/install-deps.sh)"
  exit 77
fi
if ! /usr/bin/python3 -c "import pytest, numpy, pandas" 2>/dev/null; then
  echo "skipped: /usr/bin/python3 lacks pytest, numpy or pandas (scripts/install-deps.sh installs python3-pytest, python3-numpy, python3-pandas)"
  exit 77
fi
PYTHONPATH="$pydir${PYTHONPATH:+:$PYTHONPATH}" exec /usr/bin/python3 -m pytest -q -p no:cacheprovider "$@"
