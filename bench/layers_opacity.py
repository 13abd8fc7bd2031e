#!/usr/bin/env python3
"""Prints `render --opacity` points for N narrow Gaussian layers on a log10 scale, as yt's
ColorTransferFunction.add_layers(N) places them: centres evenly spaced over [log10 LO, log10 HI]
including both ends, each alpha = PEAK * exp(-(x - c)^2 / w) with yt's default width
w = 0.001 * (log10 HI - log10 LO) / N. Each layer is sampled at 15 points over +-4 sigma
(sigma = sqrt(w / 2)), zero at the outermost; values in data units, as --opacity with --log takes.
usage: layers_opacity.py LO HI [N=6] [PEAK=0.3]"""
import math
import sys


def layer_points(lo, hi, n, peak):
    a, b = math.log10(lo), math.log10(hi)
    w = 0.001 * (b - a) / n
    sigma = math.sqrt(w / 2)
    pts = []
    for i in range(n):
        c = a + (b - a) * i / (n - 1)
        for k in (-4, -3, -2.5, -2, -1.5, -1, -0.5, 0, 0.5, 1, 1.5, 2, 2.5, 3, 4):
            x = c + k * sigma
            alpha = 0.0 if abs(k) == 4 else peak * math.exp(-((k * sigma) ** 2) / w)
            pts.append("%.7g:%.4g" % (10**x, alpha))
    return ",".join(pts)


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit("usage: layers_opacity.py LO HI [N] [PEAK]")
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 6
    peak = float(sys.argv[4]) if len(sys.argv) > 4 else 0.3
    print(layer_points(float(sys.argv[1]), float(sys.argv[2]), n, peak))
