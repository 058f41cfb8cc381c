#!/bin/sh
# `oovr simulate --timeline`: the file is Trace Event Format JSON that a JSON
# reader takes whole, with one span per unit (test_timeline.cpp checks the
# spans against the busy times), and the command says where it went.
# Usage: timeline.sh OOVR WORKDIR
set -eu
oovr=$1
work=$2
rm -rf "$work" && mkdir -p "$work"
"$oovr" simulate --scene courtyard --scheme oo-vr --resolution 320x240 --timeline "$work/t.json" > "$work/run.log" 2>&1 || {
  cat "$work/run.log"; exit 1; }
# The path compared as text (grep -F): it may hold [, ] or . of its own.
grep "^timeline: [1-9][0-9]* units in " "$work/run.log" | grep -qF "units in $work/t.json" || { cat "$work/run.log"; exit 1; }
/usr/bin/python3 - "$work/t.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
spans = [e for e in d["traceEvents"] if e["ph"] == "X" and e.get("cat") not in (None, "batch", "wait")]
waits = [e for e in d["traceEvents"] if e.get("cat") == "wait"]
assert len(waits) == d["otherData"]["waits"] > 0, (len(waits), d["otherData"])
marks = [e for e in d["traceEvents"] if e.get("cat") in ("batch", "decision")]
assert len(marks) == d["otherData"]["marks"] > 0, (len(marks), d["otherData"])
assert len(spans) == d["otherData"]["units"] > 0, (len(spans), d["otherData"])
names = {e["args"]["name"] for e in d["traceEvents"] if e["ph"] == "M" and e["name"] == "process_name"}
assert {"GPM 0", "GPM 3", "links", "frames"} <= names, names
PY
# Bounded: --timeline-events keeps the earliest and says how many it left out.
"$oovr" simulate --scene courtyard --scheme oo-vr --resolution 320x240 --timeline "$work/s.json" --timeline-events 5 \
  > "$work/small.log" 2>&1 || { cat "$work/small.log"; exit 1; }
grep "^timeline: 5 units in .*, [1-9][0-9]* later ones left out (--timeline-events)" "$work/small.log" |
  grep -qF "5 units in $work/s.json, " || {
  cat "$work/small.log"; exit 1; }
echo timeline-ok
