"""Fit the model's tables of piecewise polynomials and print them as Rust constants.

Each table is a smooth function of one variable on [0, x_max], as a polynomial of degree 8 on each
of its equal pieces, in the piece's own z ∈ [−1, 1], with monomial coefficients (lowest first) from
a Chebyshev least-squares fit at 60 nodes per piece (`src/physics/piecewise.rs` evaluates them):
- `KEPLER_OPENING` (src/physics/valve.rs), the inverse port law. The circular ports open the area
  A = (n r²/2)(φ − sin φ) at the opening h = 2r sin²(φ/4); for Kepler's equation φ − sin φ = M
  (0 ≤ M ≤ π) and t = (6M)^(2/3) the opening fraction is sin²(φ/4) = (t/16)·W(t). This fits W.
- `SEGMENT_AREA` (valve.rs), the port law: with u = h/r ≤ 1 a port's open area is r²·u^(3/2)·G(u).
  This fits G.
- `MOUNT_DEFLECTION` (src/physics/mount.rs), the cubic mount's inverse: F = k1 δ + k3 δ³ has the
  root δ = u (1 + ε P(ε)), u = F/k1, ε = k3 u²/k1, where P solves P = −(1 + ε P)³. This fits P.
Every function is computed in double precision without cancellation: φ − sin φ from its series
below φ = 1, Newton's method on Kepler's equation and on P's.

    python3 scripts/fit_tables.py            # print the tables
    python3 scripts/fit_tables.py --check    # the worst relative error of each fit

tests/python/test_fitted_tables.py checks that the tables in the source are this script's fits.
"""

import argparse
import math

import numpy as np

DEGREE = 8
NODES = 60
T_MAX = (6.0 * math.pi) ** (2.0 / 3.0)


def kepler(phi: float) -> float:
    """φ − sin φ, from its series below φ = 1 (terms to φ²⁵), where the difference cancels."""
    if phi >= 1.0:
        return phi - math.sin(phi)
    x2 = phi * phi
    term, total = phi * x2 / 6.0, 0.0
    for k in range(1, 13):
        total += term
        n = 2 * k + 1
        term *= -x2 / ((n + 1) * (n + 2))
    return total


def opening_factor(t: float) -> float:
    """W(t) = sin²(φ/4)/(t/16) at the root φ of φ − sin φ = t^(3/2)/6."""
    m = t**1.5 / 6.0
    phi = math.sqrt(t)  # the root's leading term, (6M)^(1/3)
    for _ in range(50):
        step = (kepler(phi) - m) / (1.0 - math.cos(phi) if phi > 1e-4 else phi * phi / 2.0)
        phi -= step
        if abs(step) <= 1e-17 * phi:
            break
    return math.sin(phi / 4.0) ** 2 / (t / 16.0)


def segment_factor(u: float) -> float:
    """G(u) = α(u)/u^(3/2), α(u) = acos(1 − u) − (1 − u)·sqrt(u(2 − u)) = (φ − sin φ)/2, the open
    area of a port of unit radius at the opening u, with φ = 4 asin(sqrt(u/2))."""
    return kepler(4.0 * math.asin(math.sqrt(u / 2.0))) / 2.0 / u**1.5


def mount_factor(e: float) -> float:
    """P(ε), the root of P + (1 + ε P)³ = 0 near −1: the cubic mount's δ = u (1 + ε P)."""
    p = -1.0
    for _ in range(50):
        d = 1.0 + e * p
        step = (p + d**3) / (1.0 + 3.0 * e * d * d)
        p -= step
        if abs(step) <= 1e-17 * abs(p):
            break
    return p


# name: (function, the name of the constant for x_max or None, x_max, pieces)
TABLES = {
    "KEPLER_OPENING": (opening_factor, "KEPLER_T_MAX", T_MAX, 8),
    "SEGMENT_AREA": (segment_factor, None, 1.0, 8),
    "MOUNT_DEFLECTION": (mount_factor, "MOUNT_SHARE_MAX", 0.25, 16),
}


def fit(function, x_max: float, pieces: int) -> list[np.ndarray]:
    """Monomial coefficients in z ∈ [−1, 1], lowest first, of each piece of `function` on [0, x_max]."""
    z = np.cos(np.pi * (np.arange(NODES) + 0.5) / NODES)
    rows = []
    for k in range(pieces):
        a, b = k * x_max / pieces, (k + 1) * x_max / pieces
        values = np.array([function(0.5 * (b - a) * zi + 0.5 * (a + b)) for zi in z])
        chebyshev = np.polynomial.chebyshev.Chebyshev.fit(z, values, DEGREE, domain=[-1, 1])
        rows.append(np.polynomial.chebyshev.cheb2poly(chebyshev.coef))
    return rows


def evaluate(rows: list, x_max: float, x: float) -> float:
    """A fitted table at x, as piecewise.rs evaluates it (up to the order of the operations)."""
    pieces = len(rows)
    piece = min(int(x * pieces / x_max), pieces - 1)
    z = x * 2.0 * pieces / x_max - (2 * piece + 1)
    return float(np.polynomial.polynomial.polyval(z, rows[piece]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="print each fit's worst relative error")
    args = parser.parse_args()
    for name, (function, limit, x_max, pieces) in TABLES.items():
        rows = fit(function, x_max, pieces)
        if args.check:
            xs = x_max * np.arange(1, 4001) / 4000
            worst = max(abs(evaluate(rows, x_max, x) / function(x) - 1.0) for x in xs)
            print(f"{name}: worst relative error over 4000 points: {worst:.2e}")
            continue
        if limit:
            print(f"const {limit}: f64 = {x_max!r};")
        print(f"const {name}: [[f64; {DEGREE + 1}]; {pieces}] = [")
        for row in rows:
            print("    [" + ", ".join(repr(float(c)) for c in row) + "],")
        print("];")


if __name__ == "__main__":
    main()
