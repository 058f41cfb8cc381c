#!/bin/sh
# A sweep killed with SIGKILL in the middle and resumed gives the database
# an uninterrupted sweep gives: the same 20 runs, each once, with the same
# figures (docs/sweeps.md, "Interrupted sweeps").
# Usage: sweep_resume.sh OOVR WORKDIR
set -eu
here=$(cd "$(dirname "$0")" && pwd)
oovr=$1
work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
export OOVR_CACHE_DIR="$work/cache"
cat > twenty.toml <<'TOML'
# 20 points: 2 scenes x 2 schemes x 5 link bandwidths
scenes = ["crowd", "courtyard"]
schemes = ["baseline", "oo-vr"]
resolutions = ["640x480"]
frames = 4
images = true
[sweep]
"link.bandwidth" = ["32GBps", "64GBps", "128GBps", "256GBps", "1TBps"]
TOML

"$oovr" sweep twenty.toml --db whole.db --jobs 1 > whole.log 2>&1 || { cat whole.log; exit 1; }

# The same sweep, killed once five runs are stored.
"$oovr" sweep twenty.toml --db killed.db --jobs 1 > killed.log 2>&1 &
pid=$!
tries=0
while :; do
  n=$(sqlite3 killed.db "SELECT count(*) FROM runs" 2>/dev/null || echo 0)
  [ "$n" -ge 5 ] && break
  tries=$((tries + 1))
  [ $tries -gt 3000 ] && { echo "the sweep stored no 5 runs in 300 s"; kill -9 $pid; exit 1; }
  sleep 0.1
done
kill -9 $pid
wait $pid 2>/dev/null && { echo "the sweep ended before it was killed: nothing was tested"; exit 1; } || true
n=$(sqlite3 killed.db "SELECT count(*) FROM runs")
[ "$n" -lt 20 ] || { echo "the sweep had finished when it was killed"; exit 1; }
echo "killed with $n of 20 runs stored"

# Without --resume the database is refused, not run into again.
if "$oovr" sweep twenty.toml --db killed.db > again.log 2>&1; then echo "ran again without --resume"; exit 1; fi
grep -q "give --resume" again.log || { cat again.log; exit 1; }

"$oovr" sweep twenty.toml --db killed.db --jobs 2 --resume > resumed.log 2>&1 || { cat resumed.log; exit 1; }
grep -q "($n in the database already, $((20 - n)) to run)" resumed.log || { cat resumed.log; exit 1; }

# Everything but when, where and by which command each run was made.
dump() { sh "$here/dump_runs.sh" "$1" link.bandwidth; }
dump whole.db > whole.dump
dump killed.db > resumed.dump
# Twenty runs, each point of the sweep once (ids are the primary key, so
# count the points by their position in the sweep).
[ "$(sqlite3 killed.db "SELECT count(*), count(DISTINCT position) FROM runs WHERE status = 'done'")" = "20|20" ] || { echo "not 20 distinct runs"; exit 1; }
cmp whole.dump resumed.dump || { diff whole.dump resumed.dump | cut -c 1-300 | head -20; exit 1; }
echo "resumed sweep equals the uninterrupted one: 20 runs, $(sqlite3 killed.db "SELECT count(*) FROM metrics") metrics"
# A run kept from another build is named when the sweep is resumed.
# (Its checksum cleared, as a row of a version 1 database has none: an edit
# of a checksummed row is damage, refused.)
sqlite3 killed.db "UPDATE runs SET git_commit = '0123456789ab', checksum = NULL WHERE position = 3"
"$oovr" sweep twenty.toml --db killed.db --resume > noted.log 2>&1 || { cat noted.log; exit 1; }
grep -q "^note: 1 of the runs kept were made by oovr 0123456789ab, not by this one" noted.log || { cat noted.log; exit 1; }
echo "a run of another build is named on --resume"
