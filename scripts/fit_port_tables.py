"""Fit the valve's port-law tables in src/physics/valve.rs and print them.

The valve's circular ports open the area A = (n r²/2)(φ − sin φ) at the opening h = 2r sin²(φ/4),
φ/2 the half angle of a port's uncovered segment. Two smooth factors of this law are tabulated,
each as a polynomial of degree 8 on each of 8 equal pieces of its variable, in the piece's own
z ∈ [−1, 1], with monomial coefficients (lowest first) from a Chebyshev least-squares fit:
- `KEPLER_OPENING`, the inverse: for Kepler's equation φ − sin φ = M (0 ≤ M ≤ π) and
  t = (6M)^(2/3), the opening fraction is sin²(φ/4) = (t/16)·W(t); this fits W;
- `SEGMENT_AREA`, the law itself: with u = h/r ≤ 1 a port's open area is r²·u^(3/2)·G(u); this
  fits G (the other half by symmetry).
Both come from φ − sin φ in a form without cancellation (its series below φ = 1) and, for the
inverse, Newton's method on it, in double precision.

    python3 scripts/fit_port_tables.py            # print the tables
    python3 scripts/fit_port_tables.py --check    # the worst relative error of each fit

tests/python/test_port_tables.py checks that the tables in valve.rs are this script's fits.
"""

import argparse
import math

import numpy as np

PIECES = 8
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


TABLES = {"KEPLER_OPENING": (opening_factor, T_MAX), "SEGMENT_AREA": (segment_factor, 1.0)}


def fit(function, x_max: float) -> list[np.ndarray]:
    """Monomial coefficients in z ∈ [−1, 1], lowest first, of each piece of `function` on [0, x_max]."""
    z = np.cos(np.pi * (np.arange(NODES) + 0.5) / NODES)
    rows = []
    for k in range(PIECES):
        a, b = k * x_max / PIECES, (k + 1) * x_max / PIECES
        values = np.array([function(0.5 * (b - a) * zi + 0.5 * (a + b)) for zi in z])
        chebyshev = np.polynomial.chebyshev.Chebyshev.fit(z, values, DEGREE, domain=[-1, 1])
        rows.append(np.polynomial.chebyshev.cheb2poly(chebyshev.coef))
    return rows


def evaluate(rows: list, x_max: float, x: float) -> float:
    """A fitted table at x, as valve.rs evaluates it (up to the order of the operations)."""
    piece = min(int(x * PIECES / x_max), PIECES - 1)
    z = x * 2.0 * PIECES / x_max - (2 * piece + 1)
    return float(np.polynomial.polynomial.polyval(z, rows[piece]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="print each fit's worst relative error")
    args = parser.parse_args()
    for name, (function, x_max) in TABLES.items():
        rows = fit(function, x_max)
        if args.check:
            xs = x_max * np.arange(1, 4001) / 4000
            worst = max(abs(evaluate(rows, x_max, x) / function(x) - 1.0) for x in xs)
            print(f"{name}: worst relative error over 4000 points: {worst:.2e}")
            continue
        print(f"const {name}: [[f64; {DEGREE + 1}]; PIECES] = [")
        for row in rows:
            print("    [" + ", ".join(repr(float(c)) for c in row) + "],")
        print("];")
    if not args.check:
        print(f"const KEPLER_T_MAX: f64 = {T_MAX!r};")


if __name__ == "__main__":
    main()
