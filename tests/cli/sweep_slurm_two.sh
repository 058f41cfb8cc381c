#!/bin/sh
# `oovr sweep --backend slurm` on a two-node SLURM (two slurmd on localhost,
# each with its own port, spool, pid file and log, one CPU each): the
# default chunking gives each trace group a task, the two tasks run one on
# each node, and the collected database equals the local backend's; a job
# whose oovr is gone from the nodes' path has each node say so, and
# --collect shows it. Exits
# 77 ("skipped", with the reason) when SLURM is not installed or cannot
# start.
# Usage: sweep_slurm_two.sh OOVR WORKDIR
set -eu
here=$(cd "$(dirname "$0")" && pwd)
oovr=$1
. "$here/slurm_lib.sh"
slurm_test "$2" 2
cat > two.toml <<'TOML'
# 8 points in 2 trace groups: 2 scenes x 2 schemes x 2 GPM counts
name = "two"
scenes = ["crowd", "courtyard"]
schemes = ["baseline", "oo-vr"]
resolutions = ["160x128"]
frames = 4
[sweep]
gpms = [2, 4]
TOML
"$oovr" sweep two.toml --db local.db > local.log 2>&1 || { cat local.log; exit 1; }
"$oovr" sweep two.toml --db slurm.db --backend slurm --wait > slurm.log 2>&1 || {
  cat slurm.log; tail -n 20 slurm.db.slurm/task-*.log slurmctld.log slurmd-node*.log; exit 1; }
grep -q "8 points in 2 tasks" slurm.log || { cat slurm.log; exit 1; }
grep -q "collected 8 runs from 2 task files" slurm.log || { cat slurm.log; exit 1; }
# Each node ran a task of the array (its own slurmd launched it).
for n in node1 node2; do
  grep -q "Launching batch job" "slurmd-$n.log" || { echo "$n ran no task"; tail -n 5 slurmd-*.log; exit 1; }
done
dump() { sh "$here/dump_runs.sh" "$1" gpms; }
dump local.db > local.dump
dump slurm.db > slurm.dump
cmp local.dump slurm.dump || { diff local.dump slurm.dump | cut -c 1-300 | head -20; exit 1; }
# The oovr the nodes run is not there when the tasks start (a build folder
# the nodes do not share): each node says so in its task's log, and
# --collect shows it for each task that wrote nothing.
cp "$oovr" "$PWD/vanishing-oovr"
"$PWD/vanishing-oovr" sweep two.toml --db gone.db --backend slurm --slurm-dir gone.slurm --sbatch-arg=--hold > gone.log 2>&1 || {
  cat gone.log; exit 1; }
job=$(submitted_job gone.log)
[ -n "$job" ] || { cat gone.log; exit 1; }
rm "$PWD/vanishing-oovr"
release_and_wait "$job"
if "$oovr" sweep two.toml --db gone.db --slurm-dir gone.slurm --collect > gone-collect.log 2>&1; then cat gone-collect.log; exit 1; fi
# The path compared as text (grep -F): it may hold [, ] or . of its own.
[ "$(grep "wrote nothing .*its log ends: oovr: node node[12] has no executable " gone-collect.log |
  grep -cF "has no executable $PWD/vanishing-oovr: the nodes need this oovr")" -eq 2 ] || {
  cat gone-collect.log; tail -n 3 gone.slurm/task-*.log; exit 1; }
echo "two-node SLURM sweep equals the local one: 8 runs in 2 tasks, one on each node; a node without the oovr says so"
