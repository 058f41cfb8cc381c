#!/bin/sh
# `oovr paper` from a sweep: experiments/quick.toml on the crowd scene runs
# into the database in --out, the comparison is written there (and to
# --doc), with every claim row and the model's steps; --resume runs nothing
# again; experiments/paper.toml resolves.
# Usage: paper.sh OOVR WORKDIR SOURCE_DIR
set -eu
oovr=$1
work=$2
src=$3
rm -rf "$work" && mkdir -p "$work/doc"
"$oovr" paper --sweep "$src/experiments/quick.toml" --scenes crowd --out "$work/out" --doc "$work/doc/comparison.md" \
  > "$work/run.log" 2>&1 || { tail -n 20 "$work/run.log"; exit 1; }
for f in quick.db results.json paper-comparison.md fig15-speedup.csv fig16-traffic.csv fig17-links.csv fig18-gpms.csv \
         ablations.csv copies.csv fig15-speedup.svg fig17-links.svg fig18-gpms.svg copies.svg img/paper/fig15-speedup.svg \
         img/paper/copies.svg img/paper/fig15-speedup.pdf img/paper/fig15-speedup.png img/paper/copies.pdf; do
  [ -s "$work/out/$f" ] || { echo "missing $f"; exit 1; }
done
# Each chart as PDF (a PDF's header) and PNG beside its SVG in --out, the document's copy SVG only.
head -c 5 "$work/out/img/paper/fig17-links.pdf" | grep -q '^%PDF-' || { echo "fig17-links.pdf is not a PDF"; exit 1; }
grep -q "plots (5 charts as SVG, PDF and PNG)" "$work/run.log" || { tail -n 3 "$work/run.log"; exit 1; }
[ ! -e "$work/doc/img/paper/fig15-speedup.pdf" ] || { echo "PDFs in the document's folder"; exit 1; }
[ -s "$work/doc/comparison.md" ] && [ -s "$work/doc/img/paper/fig15-speedup.svg" ] || { echo "no --doc copy"; exit 1; }
cmp "$work/out/paper-comparison.md" "$work/doc/comparison.md" || { echo "--doc differs from --out's document"; exit 1; }
doc="$work/out/paper-comparison.md"
for c in P1 P2 P3 P4 P5 P6 P7 P8 P9 P10 P11 P12 P13 P14 P15 P16 P17 P18; do
  grep -q "^| $c |" "$doc" || { echo "missing $c"; exit 1; }
  # oovr's cells (the mean, then the scene's) hold figures: no nan, n/a or empty cell.
  row=$(grep -m 1 "^| $c |" "$doc" | cut -d '|' -f 5-)
  echo "$row" | grep -Eq '[0-9]' || { echo "$c has no figure: $row"; exit 1; }
  if echo "$row" | grep -Eqi 'nan|n/a|\| *\|'; then echo "$c has a cell without a figure: $row"; exit 1; fi
done
# Energy beside the traffic (P18): a table per scene after Figure 16's.
grep -q "^### Energy (P18)" "$doc" || { echo "no energy table"; exit 1; }
grep -Eq '^\| `crowd` \| [0-9.]+ mJ \| [0-9.]+ mJ \|' "$doc" || { grep -A4 "### Energy" "$doc"; exit 1; }
# OO-VR against copy capacity: the uncapped point and four caps per scene, as figures.
[ "$(grep -Ec '^crowd,[0-9]+,[0-9.]+,[0-9.]+,[0-9]+$' "$work/out/copies.csv")" = 5 ] || { cat "$work/out/copies.csv"; exit 1; }
grep -q "^## OO-VR's copies and the memory they live in" "$doc" || { echo "no copy capacity section"; exit 1; }
# The paper's numbers come from experiments/paper-claims.toml.
grep -q "^| P1 | baseline frame rate against 1 TB/s links | 128 GB/s -22%, 64 GB/s -42%, 32 GB/s -65% |" "$doc" || exit 1
grep -q "is 960 bits (the paper: 960 bits)" "$doc" || { echo "P16"; exit 1; }
grep -q "^## Before and after" "$doc" || { echo "no steps table"; exit 1; }
grep -q "^| P1 | -42% |" "$doc" || { echo "no P1 row in the steps table"; exit 1; }
grep -q "1 scenes (0 skipped), 119 runs (119 run now)" "$work/run.log" || { tail -n 3 "$work/run.log"; exit 1; }
# --resume: the database has every point.
"$oovr" paper --sweep "$src/experiments/quick.toml" --scenes crowd --out "$work/out" --resume > "$work/resume.log" 2>&1 || {
  tail -n 5 "$work/resume.log"; exit 1; }
grep -q "119 runs (0 run now)" "$work/resume.log" || { tail -n 3 "$work/resume.log"; exit 1; }
# The same evaluation on another machine (--set, issue 32): every point on
# it, the claims measured on it, the document saying which it is.
"$oovr" paper --sweep "$src/experiments/quick.toml" --scenes crowd --out "$work/m" --set link.bandwidth=32GBps \
  --set memory.copies.capacity=16MB --against "$work/out/quick.db" > "$work/m.log" 2>&1 || { tail -n 5 "$work/m.log"; exit 1; }
m="$work/m/paper-comparison.md"
grep -q "^| \`link.bandwidth\` | 32 GB/s | 64 GB/s | --set |" "$m" || { grep -A6 "The machine every run" "$m"; exit 1; }
grep -q "^| \`memory.copies.capacity\` | 16 MB | 0 B | --set |" "$m" || { grep -A6 "The machine every run" "$m"; exit 1; }
grep -q "Speed-up against the baseline with 32 GB/s links" "$m" || { echo "Figure 17 is not against the machine's links"; exit 1; }
# Complete: no figure is missing from the CSV files or the claims table.
if grep -l nan "$work"/m/*.csv; then echo "a figure is missing on the other machine"; exit 1; fi
for c in P1 P2 P3 P4 P5 P6 P7 P8 P9 P10 P11 P12 P13 P14 P15 P16 P17 P18; do
  row=$(grep -m 1 "^| $c |" "$m" | cut -d '|' -f 5-)
  if echo "$row" | grep -Eqi 'nan|n/a|\| *\|'; then echo "$c has a cell without a figure on the other machine: $row"; exit 1; fi
done
grep -q "points are the same run as an earlier point" "$work/m.log" || { echo "no shared points"; exit 1; }
# The claims beside the first run's, checked against the runs read back by
# hand: OO-VR's speed-up over the baseline (P10) on each machine, from the
# grid's runs (no key of their own: none from the sweep) of each database.
[ -s "$work/m/paper-against.md" ] && [ -s "$work/m/claims-against.csv" ] || { echo "no --against outputs"; exit 1; }
grep -q "^| \`link.bandwidth\` | 32 GB/s (--set) |  | 64 GB/s |" "$work/m/paper-against.md" || {
  grep -A6 "## The machines" "$work/m/paper-against.md"; exit 1; }
/usr/bin/python3 - "$work/m/quick.db" "$work/out/quick.db" "$work/m/claims-against.csv" <<'PY' || exit 1
import csv, json, sqlite3, sys
def p10(path):
    db = sqlite3.connect(path)
    lat = {}
    for run, scheme, config in db.execute(
            "SELECT id, scheme, config FROM runs WHERE scene = 'crowd' AND resolution = '640x480' AND status = 'done'"):
        if scheme in ("baseline", "oo-vr") and all(e["source"] != "sweep" for e in json.loads(config).values()):
            assert scheme not in lat, "two grid runs of " + scheme
            (lat[scheme],) = db.execute("SELECT value FROM metrics WHERE run = ? AND location = 'frame' AND metric = 'latency'",
                                        (run,)).fetchone()
    return lat["baseline"] / lat["oo-vr"]
here, there = p10(sys.argv[1]), p10(sys.argv[2])
row = [r for r in csv.DictReader(open(sys.argv[3])) if r["claim"] == "P10" and r["value"] == "oo-vr" and r["scene"] == "crowd"]
assert len(row) == 1, row
for name, by_hand, written in (("here", here, float(row[0]["here"])), ("there", there, float(row[0]["there"]))):
    assert abs(written / by_hand - 1) < 1e-5, (name, by_hand, written)
assert abs(here / there - 1) > 1e-3, ("the machines gave the same speed-up", here, there)
PY
# A sweep file's own [set] is its machine too: the same runs as --set's.
{ cat "$src/experiments/quick.toml"; printf '[set]\n"memory.copies.capacity" = "16MB"\n"link.bandwidth" = "32GBps"\n'; } \
  > "$work/quick-set.toml"
"$oovr" paper --sweep "$work/quick-set.toml" --scenes crowd --out "$work/f" > "$work/f.log" 2>&1 || { tail -n 5 "$work/f.log"; exit 1; }
grep -F '| `memory.copies.capacity` | 16 MB | 0 B | ' "$work/f/paper-comparison.md" | grep -qF 'quick-set.toml \[set\] |' || {
  grep -A6 "The machine every run" "$work/f/paper-comparison.md"; exit 1; }
for f in fig15-speedup.csv fig16-traffic.csv fig17-links.csv fig18-gpms.csv ablations.csv copies.csv; do
  cmp "$work/m/$f" "$work/f/$f" || { echo "$f differs between --set and the file's [set]"; exit 1; }
done
# On the default machine, named or not, the document is the same byte for
# byte (but for the command it names).
"$oovr" paper --sweep "$src/experiments/quick.toml" --scenes crowd --out "$work/d" --set link.bandwidth=64GBps \
  > "$work/d.log" 2>&1 || { tail -n 5 "$work/d.log"; exit 1; }
grep -v '^Generated by' "$work/out/paper-comparison.md" > "$work/a.md"
grep -v '^Generated by' "$work/d/paper-comparison.md" > "$work/b.md"
cmp "$work/a.md" "$work/b.md" || { diff "$work/a.md" "$work/b.md" | head; exit 1; }
# Bad machines are named before anything runs.
if "$oovr" paper --sweep "$src/experiments/quick.toml" --out "$work/e" --set link.bandwith=1TBps > "$work/e.log" 2>&1; then
  echo "a misspelt key ran"; exit 1; fi
grep -q "unknown configuration key 'link.bandwith' (--set)" "$work/e.log" || { cat "$work/e.log"; exit 1; }
if "$oovr" paper --sweep "$src/experiments/quick.toml" --out "$work/e" --set gpms=8 > "$work/e.log" 2>&1; then
  echo "AFR ran on 8 GPMs with 4 frames"; exit 1; fi
grep -q "so frames must be a multiple of 8 (--frames sets every point's)" "$work/e.log" || { cat "$work/e.log"; exit 1; }
if "$oovr" paper --sweep "$src/experiments/quick.toml" --out "$work/m" --against "$work/m/quick.db" > "$work/e.log" 2>&1; then
  echo "--against its own database ran"; exit 1; fi
grep -q "is this run's own database" "$work/e.log" || { cat "$work/e.log"; exit 1; }
# --against a database of another evaluation, or not one at all: named before anything runs.
if "$oovr" paper --scenes crowd --out "$work/e" --against "$work/out/quick.db" > "$work/e.log" 2>&1; then
  echo "--against a database without the sweep ran"; exit 1; fi
grep -q "holds no sweep 'paper' (it holds 'quick')" "$work/e.log" || { cat "$work/e.log"; exit 1; }
[ ! -e "$work/e/paper.db" ] || { echo "--against failed after the sweep began"; exit 1; }
if "$oovr" paper --sweep "$src/experiments/quick.toml" --out "$work/e" --against "$src/README.md" > "$work/e.log" 2>&1; then
  echo "--against a text file ran"; exit 1; fi
grep -q "README.md" "$work/e.log" || { cat "$work/e.log"; exit 1; }
# The full evaluation's file parses and resolves (oovr carries it, built from it).
"$oovr" sweep "$src/experiments/paper.toml" --list > "$work/list.txt"
tail -n 1 "$work/list.txt" > "$work/file.txt"
grep -q "^sweep 'paper': [1-9][0-9]* points$" "$work/file.txt" || { cat "$work/file.txt"; exit 1; }
echo paper-ok
