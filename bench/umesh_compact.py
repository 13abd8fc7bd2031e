#!/usr/bin/env python3
"""Sampling speed of the compact mesh encoding against the reference one (issue 13).

Renders each mesh dataset with `--encoding reference` and `--encoding compact` in turn, REPEATS
rounds, in one run (so both see the same machine load), with the view and transfer function of
bench/umesh_vs_vtk.sh's haze look (every element on some visible ray). Reports per encoding the
render time volstream prints (the render launch alone, not the load), samples per second, the
per-round ratio compact/reference (median [min..max]), and the RMSE of the two images in 8-bit
units (bench/png_compare.py).

usage: bench/umesh_compact.py DATASET [DATASET ...] [--vs build/volstream] [--repeats 5]
       [--size 512x512] [--out /tmp/umesh_compact]
"""
import argparse
import os
import re
import statistics
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
VIEW = [
    "--field", "density", "--range", "0.02,1.1", "--unit-distance", "0.01",
    "--camera-pos", "2.3,1.6,2.9", "--camera-at", "0.5,0.5,0.5", "--camera-up", "0,1,0", "--fov", "35",
    "--background", "0.06,0.06,0.08", "--tf", "viridis", "--device", "cpu",
    "--opacity", "0.02:0.004,0.15:0.004,0.5:0.03,1.1:0.12",
]


def render(vs, dataset, encoding, size, png):
    out = subprocess.run([vs, "render", dataset, "-o", png, "--size", size, "--encoding", encoding] + VIEW,
                         capture_output=True, text=True, check=True).stdout
    launch = re.search(r"launches: render 1 x ([0-9.]+) ms", out)
    samples = re.search(r"([0-9.]+) M samples,", out)
    memory = re.search(r"memory: host ([0-9.]+) MiB", out)
    if not (launch and samples and memory):
        sys.exit(f"cannot read the render's figures from:\n{out}")
    return float(launch.group(1)) / 1000.0, float(samples.group(1)), float(memory.group(1))


def spread(values, fmt="%.3f"):
    return (fmt + " [" + fmt + ".." + fmt + "]") % (statistics.median(values), min(values), max(values))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("datasets", nargs="+")
    ap.add_argument("--vs", default=os.path.join(HERE, "..", "build", "volstream"))
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--size", default="512x512")
    ap.add_argument("--out", default="/tmp/umesh_compact")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    print("| dataset | reference render s | compact render s | compact / reference speed, per round | "
          "M samples | host MiB reference / compact | RMSE (8-bit) |")
    print("|---|---|---|---|---|---|---|")
    for dataset in a.datasets:
        name = os.path.basename(os.path.normpath(dataset))
        times = {"reference": [], "compact": []}
        ratios, memory, samples = [], {}, 0.0
        for _ in range(a.repeats):
            for encoding in ("reference", "compact"):
                png = os.path.join(a.out, f"{name}_{encoding}.png")
                seconds, samples, memory[encoding] = render(a.vs, dataset, encoding, a.size, png)
                times[encoding].append(seconds)
            ratios.append(times["reference"][-1] / times["compact"][-1])
        compare = subprocess.run([sys.executable, os.path.join(HERE, "png_compare.py"),
                                  os.path.join(a.out, f"{name}_reference.png"),
                                  os.path.join(a.out, f"{name}_compact.png")],
                                 capture_output=True, text=True, check=True).stdout
        rmse = re.search(r"rmse ([0-9.eE+-]+)", compare)
        print(f"| {name} | {spread(times['reference'])} | {spread(times['compact'])} | {spread(ratios, '%.2f')}x | "
              f"{samples:.1f} | {memory['reference']:.1f} / {memory['compact']:.1f} | "
              f"{rmse.group(1) if rmse else '?'} |", flush=True)


if __name__ == "__main__":
    main()
