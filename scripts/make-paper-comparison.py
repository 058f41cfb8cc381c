#!/usr/bin/python3
"""Regenerates docs/paper-comparison.md: oovr's values for the paper's claims
P1-P8 (Section 4; ../shared/RESEARCH.md section 1) on each scene, beside the
paper's, with the reasons where they differ.

Usage: scripts/make-paper-comparison.py [BUILD_DIR]   (default build/release)
Scenes whose data is not installed are left out (and said so).
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BUILD = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT / "build" / "release"
OOVR = BUILD / "oovr"
SCENES = ["courtyard", "crowd", "oa:oa_dm4", "oa:ctf_inyard", "oa:am_underworks2", "torcs:forza"]
RESOLUTION = "1280x1024"


def run_json(*args):
    with tempfile.NamedTemporaryFile(suffix=".json") as f:
        subprocess.run([str(OOVR), *args, "--json", f.name], check=True, capture_output=True, text=True)
        return json.loads(Path(f.name).read_text())


def pct(x):
    return f"{(x - 1) * 100:+.0f}%"


def measure(scene):
    c = run_json("compare", "--scene", scene, "--resolution", RESOLUTION)
    s = {r["scheme"]: r for r in c["schemes"]}
    base = s["baseline"]
    lat = {k: v["frame_latency_ms"] for k, v in s.items()}
    # P1: the baseline's frame rate at 128, 64 and 32 GB/s against 1 TB/s links.
    bw = {}
    for b in ["1TBps", "128GBps", "64GBps", "32GBps"]:
        r = run_json("simulate", "--scene", scene, "--resolution", RESOLUTION, "--scheme", "baseline", "--set",
                     f"link.bandwidth={b}")
        bw[b] = r["frame_latency_ms"]
    t = {k: v["inter_gpm_bytes"] for k, v in s.items()}
    # Checks of the explanations below: object-level SFR with links fast
    # enough that composition traffic costs little, and its traffic mix.
    obj_fast = run_json("simulate", "--scene", scene, "--resolution", RESOLUTION, "--scheme", "object", "--set",
                        "link.bandwidth=1TBps")["frame_latency_ms"]
    cat = s["object"]["inter_gpm_bytes_by_category"]
    comp_share = cat["composition"] / max(1, t["object"])
    busy = s["object"]["gpm_busy_cycles"]
    raw = {
        "p1_64": bw["1TBps"] / bw["64GBps"] - 1,
        "p2": s["afr"]["throughput_fps"] / base["throughput_fps"],
        "p3": lat["afr"] / lat["baseline"] - 1,
        "p4v": lat["baseline"] / lat["sfr-v"] - 1,
        "p4h": lat["baseline"] / lat["sfr-h"] - 1,
        "p5v": t["sfr-v"] / t["baseline"] - 1,
        "p5h": t["sfr-h"] / t["baseline"] - 1,
        "p6": lat["baseline"] / lat["object"] - 1,
        "p7": t["object"] / t["baseline"] - 1,
        "x_fast": bw["1TBps"] / obj_fast - 1,
        "p8_base": s["object"]["best_to_worst"] > base["best_to_worst"],
        "p8_worst": all(s["object"]["best_to_worst"] >= v["best_to_worst"] for v in s.values()),
        "x_comp": comp_share,
        "x_busiest": max(busy) / sum(busy),
        "x_texture": base["inter_gpm_bytes_by_category"]["texture"],
        "x_uneven": max(busy) / (sum(busy) / len(busy)),
    }
    checks = {
        "X1": pct(bw["1TBps"] / obj_fast),
        "X2": f"{comp_share * 100:.0f}% ({cat['composition'] / 1e6:.1f} MB)",
        "X3": f"{max(busy) / sum(busy) * 100:.0f}% (root {busy[0] / sum(busy) * 100:.0f}%)",
        "X4": f"{base['inter_gpm_bytes_by_category']['texture'] / 1e6:.1f} MB",
    }
    return raw, checks, {
        "P1": ", ".join(f"{b[:-4]} GB/s {pct(bw['1TBps'] / bw[b])}" for b in ["128GBps", "64GBps", "32GBps"]),
        "P2": f"{s['afr']['throughput_fps'] / base['throughput_fps']:.2f}x",
        "P3": pct(lat["afr"] / lat["baseline"]),
        "P4": f"V {pct(lat['baseline'] / lat['sfr-v'])}, H {pct(lat['baseline'] / lat['sfr-h'])}",
        "P5": f"V {pct(t['sfr-v'] / t['baseline'])}, H {pct(t['sfr-h'] / t['baseline'])}",
        "P6": f"{pct(lat['baseline'] / lat['object'])} ({pct(lat['sfr-v'] / lat['object'])} over SFR-V, "
              f"{pct(lat['sfr-h'] / lat['object'])} over SFR-H)",
        "P7": pct(t["object"] / t["baseline"]),
        "P8": f"{s['object']['best_to_worst']:.2f} (baseline {base['best_to_worst']:.2f})",
    }


CLAIMS = [
    ("P1", "link bandwidth sensitivity vs 1 TB/s links (frame rate)", "128 GB/s -22%, 64 GB/s -42%, 32 GB/s -65%"),
    ("P2", "AFR throughput", "1.67x"),
    ("P3", "AFR single-frame latency", "+59%"),
    ("P4", "tile SFR speed-up", "V +28%, H +3%"),
    ("P5", "tile SFR inter-GPM traffic", "V +50%, H +44%"),
    ("P6", "object-level SFR speed-up", "+60% (+32% over SFR-V, +57% over SFR-H)"),
    ("P7", "object-level SFR inter-GPM traffic", "about -40%"),
    ("P8", "object-level best-to-worst GPM time", "large (figure only)"),
]


CHECKS = [
    ("X1", "object-level SFR vs baseline, both with 1 TB/s links (frame latency)"),
    ("X2", "composition's share of object-level inter-GPM bytes"),
    ("X3", "the busiest GPM's share of object-level GPM busy time (25% is balanced)"),
    ("X4", "baseline remote texture bytes per frame"),
]


def main():
    results, raws, checks, missing = {}, {}, {}, []
    for scene in SCENES:
        try:
            raws[scene], checks[scene], results[scene] = measure(scene)
        except subprocess.CalledProcessError as e:
            missing.append(f"{scene} ({e.stderr.strip().splitlines()[-1] if e.stderr else 'failed'})")
    head = "| claim | what | paper | " + " | ".join(f"`{s}`" for s in results) + " |"
    rule = "| --- " * (3 + len(results)) + "|"
    rows = [f"| {cid} | {what} | {paper} | " + " | ".join(results[s][cid] for s in results) + " |"
            for cid, what, paper in CLAIMS]
    check_rows = [f"| {cid} | {what} | " + " | ".join(checks[s][cid] for s in results) + " |" for cid, what in CHECKS]
    check_table = "\n".join(["| check | what | " + " | ".join(f"`{s}`" for s in results) + " |",
                             "| --- " * (2 + len(results)) + "|", *check_rows])
    doc = ROOT / "docs" / "paper-comparison.md"
    def span(key, percent=True):
        vals = [r[key] for r in raws.values()]
        f = (lambda v: f"{v * 100:+.0f}%") if percent else (lambda v: f"{v:.2f}x")
        return f"{f(min(vals))} to {f(max(vals))}"

    def names(test):
        hits = [f"`{sc}`" for sc, r in raws.items() if test(r)]
        return ", ".join(hits) if hits else "no scene"

    def count(key, test):
        return sum(1 for r in raws.values() if test(r[key]))

    losses = sorted(-r["p1_64"] * 100 for r in raws.values())

    def top2(key, sign=1):
        best = sorted(raws, key=lambda sc: sign * raws[sc][key])[:2]
        return " and ".join(f"`{sc}`" for sc in best)

    ranges = dict(p1_64=f"{losses[0]:.0f}% to {losses[-1]:.0f}%", p2=span("p2", False), p3=span("p3"), p4v=span("p4v"), p4h=span("p4h"),
                  p5v=span("p5v"), p5h=span("p5h"), p6=span("p6"), p7=span("p7"), n=len(raws),
                  p5v_up=count("p5v", lambda v: v > 0), p6_down=count("p6", lambda v: v < 0),
                  p7_down=count("p7", lambda v: v < 0), p8_worst=count("p8_worst", bool),
                  p2_up=count("p2", lambda v: v > 1), p3_up=count("p3", lambda v: v > 0),
                  p4h_up=count("p4h", lambda v: v > 0),
                  p8_base=count("p8_base", bool), p8_not=len(raws) - count("p8_worst", bool), x_fast=span("x_fast"),
                  link_bound=names(lambda r: r["x_fast"] - r["p6"] >= 0.10),
                  top_loss=top2("p1_64"), top_texture=top2("x_texture", -1),
                  busiest=f"{min(r['x_busiest'] for r in raws.values()) * 100:.0f}% to "
                          f"{max(r['x_busiest'] for r in raws.values()) * 100:.0f}%",
                  uneven=span("x_uneven", False),
                  x_comp=f"{min(r['x_comp'] for r in raws.values()) * 100:.0f}% to "
                         f"{max(r['x_comp'] for r in raws.values()) * 100:.0f}%")
    doc.write_text(TEMPLATE.format(resolution=RESOLUTION, table="\n".join([head, rule, *rows]), checks=check_table,
                                   **ranges,
                                   missing=("Not measured (data not installed): " + ", ".join(missing) + ".\n")
                                   if missing else ""))
    print(f"wrote {doc} ({len(results)} scenes)")


TEMPLATE = """# oovr against the paper's Section 4

The paper characterises the existing parallel rendering schemes on a 4-GPM NUMA system (its
Section 4); `../shared/RESEARCH.md` lists its claims P1-P8. This page puts oovr's values for
each claim beside the paper's, per scene, and explains where they differ. The model was not tuned
to the paper's numbers.

Generated by `scripts/make-paper-comparison.py` from `oovr compare` and `oovr simulate`
(`--set link.bandwidth=...` for P1) at {resolution} on the paper's Table 1 machine
(`configs/paper-table1.toml`). Every scheme is measured on the same frames, 0 to 3 of each camera
path (AFR has the four in flight, one per GPM; the others render each alone), and the figures are
means per frame. Speed-ups are frame latencies (or throughput for P2) against the baseline;
traffic is inter-GPM bytes, once per transfer.

{table}

{missing}
The explanations below are checked by a second set of runs (same scenes and settings):

{checks}

## Where oovr agrees

- **P1, direction.** The baseline slows monotonically as link bandwidth falls (a test asserts it).
- **P2 and P3, direction.** AFR has a higher throughput than the baseline on {p2_up} of {n}
  scenes ({p2} of the baseline's) and a worse single-frame latency on {p3_up} ({p3}). It moves nothing between GPMs and holds a copy of everything on
  every GPM (a test asserts both).
- **P4, SFR-V.** Vertical strips change the frame time by {p4v} against the baseline. The paper
  measured +28%.
- **P5, SFR-V.** Vertical strips move more bytes between GPMs than the baseline on {p5v_up} of
  {n} scenes ({p5v}).
  - The baseline deals an eye's tiles out in framebuffer blocks, so its framebuffer stays local.
  - The strips cut through textures and through framebuffer pages, and they repeat each draw's
    geometry on every GPM they cover.
- **P8.** Round-robin objects leave the GPMs more unbalanced than the baseline on {p8_base} of
  {n} scenes: a few objects (the floor, the sky, large brushes) carry most of the pixels, and
  the root GPM also composes. Only horizontal strips are as uneven (more so on {p8_not} scenes),
  where a scene's work piles up at one height: forza's upper strip is bare sky.

## Where oovr differs, and why

- **P1, magnitude.** At 64 GB/s the baseline loses {p1_64} of its 1 TB/s frame rate, against the
  paper's 42%. The loss follows the remote texture traffic (X4): it is largest on {top_loss};
  the most texture bytes cross the links on {top_texture}.
  - The scenes' texture working sets are a few MB per frame, against tens of MB for Doom 3 or
    Half-Life 2 at 1600x1200 with 16x anisotropic filtering.
  - Much of what crosses the links is caught by the 1 MB remote cache and the L2s, and the
    framebuffer is local by construction.
  - The paper's baseline spent most of its time waiting on links; this one spends much of its
    time shading.
- **P3, magnitude.** AFR's single-frame latency is {p3} against the baseline, not +59%.
  - Each GPM has a quarter of the machine, so a frame on one GPM takes several times longer.
  - The paper measured AFR against a baseline already slowed by NUMA traffic. Here the baseline
    is fast, so one GPM's frame looks slower next to it.
  - For the same reason, AFR's throughput gain ({p2}) spreads around the paper's 1.67x.
- **P4 and P6.** Object-level SFR is slower than the baseline on {p6_down} of {n} scenes
  ({p6}), and SFR-H depends on the scene ({p4h}).
  - Sort-last composition ships, after every object, the colour and depth of each line the
    object wrote to the root, over 64 GB/s links into one GPM, and the root's ROPs merge it
    while it renders its own share. Composition is {x_comp} of object-level inter-GPM bytes
    (check X2), as much as the baseline's whole remote texture traffic (X4).
  - With 1 TB/s links on both sides, object-level SFR comes to {x_fast} against the baseline
    (X1). It gains at least 10 points over P6 on {link_bound}: there the links into the root
    were the main loss.
  - The rest is imbalance (P8). Dealt round-robin, the busiest GPM carries {busiest} of all
    GPM busy time where 25% would be balanced (X3): it works {uneven} as long as an even split
    of the same work would take. On the built-in scenes the busiest GPM is the root, which also
    composes, and a few objects it draws (floor, sky) carry most of the pixels.
  - Each object's two views are separate tasks, so geometry is done twice.
  - The paper reports +60%. Its object-level SFR must have paid far less for composition than
    its baseline paid in remote texture traffic. With these scenes' small texture working sets,
    the balance tips the other way.
  - Horizontal strips are as unbalanced as the scene is from top to bottom: SFR-H beats the
    baseline on {p4h_up} of {n} scenes, and loses where the upper strips are mostly sky.
- **P5, SFR-H ({p5h}), and P7 ({p7}; below the baseline on {p7_down} of {n} scenes).**
  - Horizontal strips span both eyes, so SMP shares the geometry and texture data of the two
    views inside one GPM. Their traffic falls far below the baseline's instead of rising by
    +44%.
  - Object-level traffic depends on what composition moves against what texture locality saves.

The model's parts are described in [model.md](model.md); what it leaves out (coherence, DRAM
detail, packet overheads, latency hidden by parallelism within a GPM) bounds these comparisons.
"""

if __name__ == "__main__":
    main()
