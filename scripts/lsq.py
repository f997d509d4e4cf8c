"""Least squares shared by the studies' scripts (phase-map-0.2m, thesis-scale/sweep)."""
import math


def line_fit(xs, ys):
    """y = c + b x by least squares: (b, standard error of b, c, standard error of c, residual variance).
    The errors are nan with fewer than three points."""
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    b = sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx
    c = my - b * mx
    res = sum((y - c - b * x) ** 2 for x, y in zip(xs, ys))
    s2 = res / (n - 2) if n > 2 else float('nan')
    return b, math.sqrt(s2 / sxx), c, math.sqrt(s2 * (1 / n + mx * mx / sxx)), s2
