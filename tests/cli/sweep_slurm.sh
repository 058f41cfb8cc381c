#!/bin/sh
# `oovr sweep --backend slurm` on a real SLURM: starts a one-node cluster
# (slurmctld and slurmd on localhost, no munge: auth/none), runs a small
# sweep through an sbatch job array, collects the tasks' files, checks the
# database equals the local backend's, and shuts SLURM down. Exits 77
# ("skipped", with the reason) when SLURM is not installed or cannot start.
# Usage: sweep_slurm.sh OOVR WORKDIR
set -eu
here=$(cd "$(dirname "$0")" && pwd)
oovr=$1
. "$here/slurm_lib.sh"
slurm_test "$2" 1

cat > small.toml <<'TOML'
# 8 points: 2 scenes x 2 schemes x 2 GPM counts
name = "small"
scenes = ["crowd", "courtyard"]
schemes = ["baseline", "oo-vr"]
resolutions = ["160x128"]
frames = 8
images = true
[sweep]
gpms = [2, 4]
TOML
"$oovr" sweep small.toml --db local.db > local.log 2>&1 || { cat local.log; exit 1; }
"$oovr" sweep small.toml --db slurm.db --backend slurm --chunk 3 --array-limit 2 --wait > slurm.log 2>&1 || {
  cat slurm.log; tail -n 20 slurm.db.slurm/task-*.log slurmctld.log slurmd.log; exit 1; }
cat slurm.log
grep -q "8 points in 3 tasks" slurm.log || exit 1
grep -q "collected 8 runs from 3 task files" slurm.log || exit 1
# Collecting again adds nothing.
"$oovr" sweep small.toml --db slurm.db --collect > collect.log 2>&1 || { cat collect.log; exit 1; }
grep -q "collected 0 runs from 3 task files into slurm.db (8 there already)" collect.log || { cat collect.log; exit 1; }

dump() { sh "$here/dump_runs.sh" "$1" gpms; }
dump local.db > local.dump
dump slurm.db > slurm.dump
[ "$(sqlite3 slurm.db "SELECT count(*) FROM runs WHERE status = 'done'")" = 8 ] || { echo "not 8 runs done"; exit 1; }
cmp local.dump slurm.dump || { diff local.dump slurm.dump | cut -c 1-300 | head -20; exit 1; }
# What reaches the sbatch script from the user: a sweep name with a new
# line is refused before anything is written; a job folder whose name holds
# shell syntax is quoted, and the job runs without running it.
printf 'name = "x\\ntouch PWNED\\n#"\nscenes = ["crowd"]\nschemes = ["baseline"]\nresolutions = ["160x128"]\nframes = 4\n' > evil.toml
if "$oovr" sweep evil.toml --db evil.db --backend slurm --wait > evil.log 2>&1; then cat evil.log; exit 1; fi
grep -q "is not a sweep name" evil.log || { cat evil.log; exit 1; }
cat > one.toml <<'TOML'
name = "one"
scenes = ["crowd"]
schemes = ["baseline"]
resolutions = ["160x128"]
frames = 4
TOML
odd='job $(touch PWNED) `touch PWNED2`; touch PWNED3 #'
"$oovr" sweep one.toml --db one.db --backend slurm --slurm-dir "$odd" --wait > one.log 2>&1 || {
  cat one.log; tail -n 20 "$odd"/task-*.log; exit 1; }
grep -q "collected 1 runs from 1 task files" one.log || { cat one.log; exit 1; }
for f in PWNED PWNED2 PWNED3 "$odd/PWNED" "$work/PWNED"; do
  [ ! -e "$f" ] || { echo "the job folder's name ran as a command ($f)"; exit 1; }
done
# Collected before the job has run (held), the missing points are said to be
# coming, not to be run with --resume; released and ended, they are collected.
"$oovr" sweep one.toml --db held.db --backend slurm --sbatch-arg=--hold > held.log 2>&1 || { cat held.log; exit 1; }
job=$(submitted_job held.log)
[ -n "$job" ] || { cat held.log; exit 1; }
if "$oovr" sweep one.toml --db held.db --collect > early.log 2>&1; then cat early.log; exit 1; fi
grep -q "0 of 1 points in the database, 0 of them failed; job $job still has 1 task queued or running (squeue -j $job): collect again once it has ended" early.log || {
  cat early.log; exit 1; }
release_and_wait "$job"
"$oovr" sweep one.toml --db held.db --collect > late.log 2>&1 || { cat late.log; tail -n 20 held.db.slurm/task-*.log; exit 1; }
grep -q "collected 1 runs from 1 task files" late.log || { cat late.log; exit 1; }
echo "SLURM sweep equals the local one: 8 runs in 3 array tasks, a hostile sweep name refused, a hostile job folder quoted, an early collect told to wait"
