#!/usr/bin/env python3
"""The paper's Figure 4 from Python: the baseline's frame rate at lower inter-GPM link bandwidths,
against 1 TB/s links (Section 2.3; claim P1: 128 GB/s -22%, 64 GB/s -42%, 32 GB/s -65%), with
object-level SFR and OO-VR beside it (claim P13: OO-VR nearly flat). The paper's values are read
from experiments/paper-claims.toml, oovr's are simulated here, and the plot is saved as a PNG.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/link_bandwidth.py --out out/figure4.png

Each scene is loaded once and each frame rendered once: the loop over bandwidths and schemes
replays the same traces (oovr.trace_stats() says so at the end).
"""

import argparse
import os
import sys
import tomllib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import oovr  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
BANDWIDTHS = ["32GBps", "64GBps", "128GBps", "1TBps"]
SCHEMES = ["baseline", "object", "oo-vr"]


def paper_p1():
    """The paper's P1 values, {bandwidth: ratio against 1 TB/s} (the bandwidths it gives a number for)."""
    with open(os.path.join(HERE, "..", "experiments", "paper-claims.toml"), "rb") as f:
        claims = tomllib.load(f)["claim"]
    p1 = next(c for c in claims if c["id"] == "P1")
    return {v.get("set", {}).get("link.bandwidth", "64GBps"): v["paper"] for v in p1["value"] if "paper" in v}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenes", default="courtyard,crowd,oa:oa_dm4",
                    help="comma-separated; scenes whose game data is not installed are left out")
    ap.add_argument("--resolution", default="1280x1024", help="the whole stereo frame, WxH")
    ap.add_argument("--out", default="out/link-bandwidth.png")
    a = ap.parse_args(argv)

    rows = []  # (scene, scheme, bandwidth, speed-up against the same scheme at 1 TB/s)
    scenes = []
    for scene in a.scenes.split(","):
        try:
            oovr.load_scene(scene)
        except FileNotFoundError as e:
            print(f"{scene}: left out ({e})")
            continue
        scenes.append(scene)
        latency = {}
        for bw in BANDWIDTHS:
            c = oovr.compare(scene, SCHEMES, oovr.config(link__bandwidth=bw), resolution=a.resolution)
            for r in c.results:
                latency[r.scheme, bw] = r.frame_latency_s
        for scheme in SCHEMES:
            for bw in BANDWIDTHS[:-1]:
                rows.append((scene, scheme, bw, latency[scheme, "1TBps"] / latency[scheme, bw]))
    if not scenes:
        print("no scene to simulate")
        return 1

    paper = paper_p1()
    print(f"{'scene':<12} {'scheme':<9} " + " ".join(f"{bw:>8}" for bw in BANDWIDTHS[:-1]))
    for scene in scenes:
        for scheme in SCHEMES:
            vals = [v for s, sc, bw, v in rows if s == scene and sc == scheme]
            print(f"{scene:<12} {scheme:<9} " + " ".join(f"{v:>8.2f}" for v in vals))
    print(f"{'the paper':<12} {'baseline':<9} " + " ".join(f"{paper[bw]:>8.2f}" for bw in BANDWIDTHS[:-1]))

    fig, axes = plt.subplots(1, len(SCHEMES), figsize=(4 * len(SCHEMES), 3.6), sharey=True)
    width = 0.8 / len(scenes)
    for ax, scheme in zip(axes, SCHEMES):
        for i, scene in enumerate(scenes):
            vals = [v for s, sc, bw, v in rows if s == scene and sc == scheme]
            ax.bar([k + (i - (len(scenes) - 1) / 2) * width for k in range(len(vals))], vals, width, label=f"oovr: {scene}")
        if scheme == "baseline":
            ax.scatter(range(len(BANDWIDTHS) - 1), [paper[bw] for bw in BANDWIDTHS[:-1]], marker="D", color="black",
                       zorder=3, label="the paper (P1)")
        ax.set_xticks(range(len(BANDWIDTHS) - 1), [bw.replace("GBps", " GB/s") for bw in BANDWIDTHS[:-1]])
        ax.set_title(scheme)
        ax.set_xlabel("inter-GPM link bandwidth")
        ax.axhline(1.0, color="grey", linewidth=0.5)
    axes[0].set_ylabel("frame rate against 1 TB/s links (x)")
    axes[0].legend(fontsize=7, loc="lower left")
    fig.suptitle(f"Link bandwidth sensitivity, 4 GPMs, {a.resolution} (the paper's Figure 4)")
    fig.tight_layout()
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    fig.savefig(a.out, dpi=120)
    stats = oovr.trace_stats()
    print(f"plot: {a.out}; {stats['frames_rendered']} frames rendered, {stats['frames_from_disk']} read from the "
          f"trace cache, {stats['windows_reused']} windows replayed from memory")
    return 0


if __name__ == "__main__":
    sys.exit(main())
