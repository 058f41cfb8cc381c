#!/bin/sh
# Prints what two results databases of the same sweep must agree on: every
# run (all but when, where and by which command it was made), its metrics
# and its images, in id order. Usage: dump_runs.sh RESULTS.db SWEPT_COLUMN
# The swept column must exist: SQLite would read a double-quoted name that
# is no column as a string, and every database would agree on it.
sqlite3 "$1" "SELECT name FROM pragma_table_info('runs')" | grep -qx "$2" || { echo "runs has no column '$2'"; exit 1; }
sqlite3 "$1" "SELECT id, sweep, position, scene, scheme, resolution, frame, frames, aniso, config, status, error,
                     oovr_version, git_commit, result, \"$2\" FROM runs ORDER BY id;
              SELECT * FROM metrics ORDER BY run, location, metric;
              SELECT run, kind, width, height, hex(data), legend FROM images ORDER BY run, kind;"
