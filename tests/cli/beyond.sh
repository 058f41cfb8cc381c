#!/bin/sh
# `oovr beyond` from a small study: the carried experiments/beyond.toml's
# points on the courtyard at 320x240 run into the database in --out, the
# document is written there (and to --doc) with every section, figures in
# the GPUpd and CHOPIN tables and the published ratios beside them;
# --resume runs nothing again; experiments/beyond.toml resolves.
# Usage: beyond.sh OOVR WORKDIR SOURCE_DIR
set -eu
oovr=$1
work=$2
src=$3
rm -rf "$work" && mkdir -p "$work/doc"
# The study's own file at a small resolution, on the built-in scene.
sed -e 's/^scenes = .*/scenes = ["courtyard"]/' -e 's/1280x1024/320x240/g' -e 's/^name = .*/name = "beyond-small"/' \
  "$src/experiments/beyond.toml" > "$work/small.toml"
grep -q '320x240' "$work/small.toml" || { echo "the study's resolution moved: edit this test"; exit 1; }
"$oovr" beyond --sweep "$work/small.toml" --out "$work/out" --doc "$work/doc/beyond.md" --jobs 2 \
  > "$work/run.log" 2>&1 || { tail -n 20 "$work/run.log"; exit 1; }
for f in beyond-small.db runs.csv beyond-paper.md img/beyond/speedup.svg img/beyond/gpms.svg img/beyond/links.svg \
         img/beyond/traffic.svg img/beyond/balance.svg; do
  [ -s "$work/out/$f" ] || { echo "missing $f"; exit 1; }
done
[ -s "$work/doc/beyond.md" ] && [ -s "$work/doc/img/beyond/gpms.svg" ] || { echo "no --doc copy"; exit 1; }
cmp "$work/out/beyond-paper.md" "$work/doc/beyond.md" || { echo "--doc differs from --out's document"; exit 1; }
doc="$work/out/beyond-paper.md"
for h in "## At 4 GPMs" "## Against the GPM count" "## Against the link bandwidth" "## Traffic between GPMs by category" \
         "## Balance" "## GPUpd against primitive duplication" "## CHOPIN against GPUpd" \
         "## oovr's idea: OO-VR with screen affinity"; do
  grep -q "^$h" "$doc" || { echo "missing section: $h"; exit 1; }
done
# Every scheme's row at 4 GPMs, over GPM counts and link bandwidths holds figures.
for s in baseline sfr-v sfr-lb object per-eye gpupd chopin oo-vr oo-vr-affinity; do
  n=$(grep -c "^| \`$s\` | [0-9]" "$doc")
  [ "$n" -ge 4 ] || { echo "$s: $n rows with figures"; grep "^| \`$s\`" "$doc"; exit 1; }
done
# The published ratios, and oovr's beside them, as figures.
grep -q "GPUpd is 4.98x one GPU and primitive duplication 3.07x" "$doc" || { echo "GPUpd's published numbers"; exit 1; }
grep -q "CHOPIN is 1.25x GPUpd (geometric mean), up to 1.56x" "$doc" || { echo "CHOPIN's published numbers"; exit 1; }
for row in "^| courtyard | [0-9.]*x | [0-9.]*x | [0-9.]*x | [0-9.]*x | [0-9.]*x |$" \
           "^| courtyard | [0-9.]*x | [0-9]* ([0-9]*) | [0-9.]*x | [0-9.]* |$"; do
  grep -q "$row" "$doc" || { echo "no row with figures: $row"; grep "^| courtyard" "$doc"; exit 1; }
done
if grep -q "n/a" "$doc"; then echo "a figure is missing:"; grep -n "n/a" "$doc" | head; exit 1; fi
# runs.csv: one line per run, and the header.
runs=$(sed -n 's/.* \([0-9][0-9]*\) runs (\([0-9][0-9]*\) run now).*/\1 \2/p' "$work/run.log")
total=${runs% *}
[ "$runs" = "$total $total" ] || { echo "runs: $runs"; tail -n 3 "$work/run.log"; exit 1; }
[ "$(wc -l < "$work/out/runs.csv")" = $((total + 1)) ] || { echo "runs.csv: $(wc -l < "$work/out/runs.csv") lines, $total runs"; exit 1; }
# --resume: the database has every point.
"$oovr" beyond --sweep "$work/small.toml" --out "$work/out" --resume > "$work/resume.log" 2>&1 || {
  tail -n 5 "$work/resume.log"; exit 1; }
grep -q "$total runs (0 run now)" "$work/resume.log" || { tail -n 3 "$work/resume.log"; exit 1; }
# On another machine (--set): every figure, against that machine's links, and the machine named.
"$oovr" beyond --sweep "$work/small.toml" --out "$work/m" --set link.bandwidth=128GBps --jobs 2 > "$work/m.log" 2>&1 || {
  tail -n 5 "$work/m.log"; exit 1; }
m="$work/m/beyond-paper.md"
if grep -q "n/a" "$m"; then echo "a figure is missing on another machine:"; grep -n "n/a" "$m" | head; exit 1; fi
grep -q "The machine is the paper's Table 1 with \`link.bandwidth\` = 128 GB/s (--set)" "$m" || { sed -n 9p "$m"; exit 1; }
grep -q "^Speed-up over the baseline at 128 GB/s, geometric mean" "$m" || { grep -A1 "## Against the link" "$m"; exit 1; }
# The study's file parses and resolves (oovr carries it, built from it).
"$oovr" sweep "$src/experiments/beyond.toml" --list > "$work/list.txt"
tail -n 1 "$work/list.txt" > "$work/file.txt"
grep -q "^sweep 'beyond': [1-9][0-9]* points$" "$work/file.txt" || { cat "$work/file.txt"; exit 1; }
echo beyond-ok
