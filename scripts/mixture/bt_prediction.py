#!/usr/bin/env python3
"""The Barrat-Trizac / Garzo-Dufty bulk temperature ratio T2/T1 of a homogeneously heated
binary mixture (Gaussian approximation, rotations neglected), for the mixture paper's
parameters. See docs/results/mixture/report.md, "The plateau". Usage: python3 scripts/mixture/bt_prediction.py"""

m = [1.58e-5, 5.21e-6]             # kg, heavy (1) and light (2)
a = [[0.93, 0.8], [0.8, 0.7]]      # restitutions r11, r12, r22


def loss(i, T):
    """Energy lost per grain of species i per unit time, up to a factor common to all pairs."""
    total = 0.0
    for j in range(2):
        M = m[i] + m[j]
        mij, mu_ji, al = m[i] * m[j] / M, m[j] / M, a[i][j]
        s2 = T[i] / m[i] + T[j] / m[j]
        total += mij * (1 + al) * s2 ** 1.5 * ((T[i] - T[j]) / (M * s2) + mu_ji * (1 - al) / 2)
    return total


def bisect(f, lo, hi):
    flo = f(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (f(mid) > 0) == (flo > 0):
            lo, flo = mid, f(mid)
        else:
            hi = mid
    return 0.5 * (lo + hi)


cases = {
    "same random acceleration (Barrat-Trizac)": lambda g: loss(0, [1, g]) / m[0] - loss(1, [1, g]) / m[1],
    "free cooling": lambda g: loss(0, [1, g]) - loss(1, [1, g]) / g,
    "same random force": lambda g: loss(0, [1, g]) * m[0] - loss(1, [1, g]) * m[1],
}
for name, f in cases.items():
    print(f"{name}: T2/T1 = {bisect(f, 0.05, 3.0):.4f}")
