#!/bin/sh
# `oovr sweep FILE --set key=value`: overrides the file's [set] for every
# point (its ids are those of the file edited so), refuses a key the file
# sweeps or a point sets, keeps the overridden definition with the results
# so that --resume with the same --set runs nothing and without it is told
# the definition differs.
# Usage: sweep_set.sh OOVR WORKDIR
set -eu
oovr=$1
work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
fail() { echo "FAILED: $*"; exit 1; }
cat > s.toml <<'TOML'
name = "s"
scenes = ["crowd"]
schemes = ["baseline", "oo-vr"]
resolutions = ["128x96"]
frames = 1
[set]
link.latency = "32ns"
[sweep]
"link.bandwidth" = ["32GBps", "64GBps"]
[[point]]
scheme = "sfr-v"
set = { gpms = 2 }
TOML
# The file edited by hand: what --set must give, id for id.
sed 's/^link.latency = "32ns"$/link.latency = "100ns"\ngpm.draws_ahead = 8/' s.toml > edited.toml
"$oovr" sweep edited.toml --list | awk '{print $2, $3, $4, $5}' > edited.ids
"$oovr" sweep s.toml --list --set link.latency=100ns --set gpm.draws_ahead=8 | awk '{print $2, $3, $4, $5}' > set.ids
cmp edited.ids set.ids || { diff edited.ids set.ids; fail "--set differs from the file edited"; }
"$oovr" sweep s.toml --list | awk '{print $2}' > plain.ids
! cmp -s plain.ids set.ids || fail "--set changed no id"
# Refused: a swept key, a key a point sets, no '='.
for bad in "link.bandwidth=1TBps:sweeps it" "gpms=4:a point of the sweep" "gpms:give key=value"; do
  set_arg=${bad%%:*}
  why=${bad#*:}
  if "$oovr" sweep s.toml --list --set "$set_arg" > bad.log 2>&1; then fail "--set $set_arg accepted"; fi
  grep -q "^oovr: error: --set .*$why" bad.log || { cat bad.log; fail "--set $set_arg: no clear error"; }
done
# Run, then resume with the same --set: nothing to do.
"$oovr" sweep s.toml --db s.db --jobs 2 --set link.latency=100ns > run.log 2>&1 || { tail -n 5 run.log; fail "run"; }
"$oovr" sweep s.toml --db s.db --jobs 2 --set link.latency=100ns --resume > resume.log 2>&1 || { tail -n 5 resume.log; fail "resume"; }
grep -q "(6 in the database already, 0 to run)" resume.log || { cat resume.log; fail "resume ran points again"; }
# Without --set the definition is another: said, nothing run.
if "$oovr" sweep s.toml --db s.db --resume > other.log 2>&1; then cat other.log; fail "a resume without --set ran"; fi
grep -q "^oovr: error: the database s.db holds a sweep .s. defined otherwise than s.toml" other.log || { cat other.log; fail "no clear error without --set"; }
echo sweep-set-ok
