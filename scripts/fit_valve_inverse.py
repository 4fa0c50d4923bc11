"""Fit the table of the inverse port law, `KEPLER_OPENING` in src/physics/valve.rs, and print it.

The valve's circular ports open the area A = (n r²/2)(φ − sin φ) at the opening h = 2r sin²(φ/4),
so the controller's inverse needs the root φ of Kepler's equation φ − sin φ = M (eccentricity 1)
for 0 ≤ M ≤ π. With t = (6M)^(2/3) the opening fraction is sin²(φ/4) = (t/16)·W(t), W smooth. This
fits W on equal pieces of 0 ≤ t ≤ (6π)^(2/3) by Chebyshev least squares, converts each piece to
monomials in its own z ∈ [−1, 1] and prints the Rust table. The root comes from Newton's method in
double precision on a form of φ − sin φ without cancellation (its series below φ = 1).

    python3 scripts/fit_valve_inverse.py            # print the table
    python3 scripts/fit_valve_inverse.py --check    # the worst relative error of the fit

tests/python/test_valve_inverse_table.py checks that the table in valve.rs is this script's fit.
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


def fit() -> list[np.ndarray]:
    """Monomial coefficients in z ∈ [−1, 1], lowest first, of each piece."""
    z = np.cos(np.pi * (np.arange(NODES) + 0.5) / NODES)
    rows = []
    for k in range(PIECES):
        a, b = k * T_MAX / PIECES, (k + 1) * T_MAX / PIECES
        w = np.array([opening_factor(0.5 * (b - a) * zi + 0.5 * (a + b)) for zi in z])
        chebyshev = np.polynomial.chebyshev.Chebyshev.fit(z, w, DEGREE, domain=[-1, 1])
        rows.append(np.polynomial.chebyshev.cheb2poly(chebyshev.coef))
    return rows


def evaluate(rows: list, t: float) -> float:
    """The fitted W at t, as valve.rs evaluates it (up to the order of the operations)."""
    piece = min(int(t * PIECES / T_MAX), PIECES - 1)
    z = t * 2.0 * PIECES / T_MAX - (2 * piece + 1)
    return float(np.polynomial.polynomial.polyval(z, rows[piece]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="print the fit's worst relative error")
    args = parser.parse_args()
    rows = fit()
    if args.check:
        ts = T_MAX * np.arange(1, 4001) / 4000
        worst = max(abs(evaluate(rows, t) / opening_factor(t) - 1.0) for t in ts)
        print(f"worst relative error of W over 4000 points: {worst:.2e}")
        return
    print(f"const KEPLER_T_MAX: f64 = {T_MAX!r};")
    print(f"const KEPLER_OPENING: [[f64; {DEGREE + 1}]; KEPLER_PIECES] = [")
    for row in rows:
        print("    [" + ", ".join(repr(float(c)) for c in row) + "],")
    print("];")


if __name__ == "__main__":
    main()
