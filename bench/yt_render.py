#!/usr/bin/env python3
"""yt's volume renderer on the CPU-speed benchmark's plotfile (bench/cpu_speed.sh): log density,
ColorTransferFunction.add_layers(N) over [LO, HI], SIZE x SIZE, yt's default camera (the whole
domain in view). Prints the load time and the first and second render's wall times (the second
is the fair one: the first builds yt's brick tree).
usage: yt_render.py PLOTFILE LO HI SIZE OUT.png [N=6]"""
import math
import sys
import time

import yt

yt.set_log_level(40)


def main():
    path, lo, hi, size, out = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), sys.argv[5]
    n = int(sys.argv[6]) if len(sys.argv) > 6 else 6
    t0 = time.perf_counter()
    ds = yt.load(path)
    sc = yt.create_scene(ds, ("boxlib", "density"))
    source = sc[0]
    source.set_log(True)
    tf = yt.ColorTransferFunction((math.log10(lo), math.log10(hi)))
    tf.add_layers(n, colormap="viridis")
    source.set_transfer_function(tf)
    sc.camera.resolution = (size, size)
    t1 = time.perf_counter()
    sc.render()
    t2 = time.perf_counter()
    sc.render()
    t3 = time.perf_counter()
    sc.save(out, sigma_clip=None, render=False)
    print("yt %s: load %.3fs, first render %.3fs, second render %.3fs" % (yt.__version__, t1 - t0, t2 - t1, t3 - t2))


if __name__ == "__main__":
    main()
