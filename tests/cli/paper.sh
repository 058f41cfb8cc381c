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
# The full evaluation's file parses and resolves (oovr carries it, built from it).
"$oovr" sweep "$src/experiments/paper.toml" --list > "$work/list.txt"
tail -n 1 "$work/list.txt" > "$work/file.txt"
grep -q "^sweep 'paper': [1-9][0-9]* points$" "$work/file.txt" || { cat "$work/file.txt"; exit 1; }
echo paper-ok
