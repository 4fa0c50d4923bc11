"""Derive the damper's Rosenbrock method (src/solver/rosenbrock.rs) in exact rational arithmetic.

The method: four stages sharing one LU of I/(γh) − J, the first three evaluating nothing but f(y₀)
(and J), the fourth evaluating f once, at the step's end; stiffly accurate (y₁ is the fourth
stage's point plus its increment), so that R(∞) = 0 and the end-of-step evaluation sees a check
valve or the relief valve opening within the step; order 3; the fourth stage's point is an
embedded solution of order 2, so the error estimate is the fourth increment.

In Hairer & Wanner's notation (Solving ODEs II, §IV.7, Table 7.1), with β_ij = α_ij + γ_ij:
- stiff accuracy: β_4j = b_j, b_4 = γ, α_4 = Σ α_4j = 1;
- order 3: Σ b = 1, Σ b β' = ½ − γ, Σ b α² = ⅓, Σ b β β' = ⅙ − γ + γ²;
- with f evaluated only at α = 0 and α_4 = 1, Σ b α² = b_4 = ⅓ fixes γ = ⅓ (in the L-stable range
  of four stages, about 0.22–0.57), and every order-4 residual is then fixed by the structure:
  the free parameters reach only order 5;
- the embedded solution b̂ = (α_41, α_42, α_43, 0): Σ b̂ = 1, Σ b̂ β' = ½ − γ, and R̂(∞) = 0.

Three parameters are free: b₁, b₂ and β₂₁. The script searches small fractions for the method
whose transformed coefficients (the form the code uses) are smallest, then prints them and the
checks. `--check` only verifies the chosen method.

    python3 scripts/derive_rosenbrock.py            # search, then print
    python3 scripts/derive_rosenbrock.py --check    # the chosen (b₁, b₂, β₂₁) = (−½, ½, ⅓)
"""

import argparse
import itertools
from fractions import Fraction as Fr

GAMMA = Fr(1, 3)
CHOSEN = (Fr(-1, 2), Fr(1, 2), Fr(1, 3))


def inverse(matrix):
    """The inverse of a square matrix of fractions (Gauss–Jordan)."""
    n = len(matrix)
    rows = [[Fr(x) for x in row] + [Fr(int(i == j)) for j in range(n)] for i, row in enumerate(matrix)]
    for col in range(n):
        pivot = next(r for r in range(col, n) if rows[r][col] != 0)
        rows[col], rows[pivot] = rows[pivot], rows[col]
        rows[col] = [x / rows[col][col] for x in rows[col]]
        for r in range(n):
            if r != col and rows[r][col] != 0:
                factor = rows[r][col]
                rows[r] = [x - factor * y for x, y in zip(rows[r], rows[col], strict=True)]
    return [row[n:] for row in rows]


def times(matrix, vector):
    return [sum(m * v for m, v in zip(row, vector, strict=True)) for row in matrix]


def dot(u, v):
    return sum(a * b for a, b in zip(u, v, strict=True))


def method(b1, b2, beta21):
    """The Hairer–Wanner tableau (α, β with γ on its diagonal, b) and the embedded weights."""
    g = GAMMA
    b3 = 1 - g - b1 - b2
    # Σ b β' = ½ − γ and Σ b β β' = ⅙ − γ + γ², with β₄ = b and β'₄ = 1 − γ
    order2 = Fr(1, 2) - 2 * g + g * g
    order3 = Fr(1, 6) - Fr(3, 2) * g + 3 * g * g - g**3
    beta32 = order3 / (b3 * beta21)
    beta31 = (order2 - b2 * beta21) / b3 - beta32
    beta = [[g, 0, 0, 0], [beta21, g, 0, 0], [beta31, beta32, g, 0], [b1, b2, b3, g]]
    ones = times(inverse(beta), [Fr(1)] * 4)
    # the embedded weights: Σ = 1, order 2, R̂(∞) = 1 − b̂ β⁻¹ 1 = 0
    alpha4 = times(inverse([[1, 1, 1], [0, beta21, beta31 + beta32], ones[:3]]), [Fr(1), Fr(1, 2) - g, Fr(1)])
    alpha = [[Fr(0)] * 4 for _ in range(3)] + [alpha4 + [Fr(0)]]
    return alpha, beta, [b1, b2, b3, g]


def transformed(alpha, beta, b):
    """The code's form: (I/(γh) − J) u_i = f(y + Σ a_ij u_j) + Σ (c_ij/h) u_j + γ_i h ∂f/∂t,
    y₁ = y + Σ m_i u_i, with Γ = β − α: a = α Γ⁻¹, c = −Γ⁻¹ below the diagonal, m = b Γ⁻¹."""
    gamma = [[beta[i][j] - alpha[i][j] for j in range(4)] for i in range(4)]
    inv = inverse(gamma)
    a = [[dot(alpha[i], [inv[k][j] for k in range(4)]) for j in range(4)] for i in range(4)]
    c = [[-inv[i][j] if j < i else Fr(0) for j in range(4)] for i in range(4)]
    m = [dot(b, [inv[k][j] for k in range(4)]) for j in range(4)]
    gamma_i = [sum(row) for row in gamma]
    return a, c, m, gamma_i


def checks(alpha, beta, b):
    """Each condition's residual, exactly; all zero for the method, the order-4 ones for show."""
    g = GAMMA
    strict = [[beta[i][j] if j < i else Fr(0) for j in range(4)] for i in range(4)]
    beta_sum = [sum(row) for row in strict]
    alpha_sum = [sum(row) for row in alpha]
    embedded = alpha[3]
    return {
        "Σ b = 1": sum(b) - 1,
        "Σ b β' = ½ − γ": dot(b, beta_sum) - (Fr(1, 2) - g),
        "Σ b α² = ⅓": dot(b, [x * x for x in alpha_sum]) - Fr(1, 3),
        "Σ b β β' = ⅙ − γ + γ²": dot(b, times(strict, beta_sum)) - (Fr(1, 6) - g + g * g),
        "stiffly accurate: β₄ = b, α₄ = 1": sum(abs(beta[3][j] - b[j]) for j in range(4)) + abs(alpha_sum[3] - 1),
        "embedded Σ b̂ = 1": sum(embedded) - 1,
        "embedded Σ b̂ β' = ½ − γ": dot(embedded, beta_sum) - (Fr(1, 2) - g),
        "R(∞) = 1 − b β⁻¹ 1 = 0": 1 - dot(b, times(inverse(beta), [Fr(1)] * 4)),
        "R̂(∞) = 0": 1 - dot(embedded, times(inverse(beta), [Fr(1)] * 4)),
    }, {
        "Σ b α³ − ¼": dot(b, [x**3 for x in alpha_sum]) - Fr(1, 4),
        "Σ b α (α β') − (⅛ − γ/3)": dot(b, [x * y for x, y in zip(alpha_sum, times(alpha, beta_sum), strict=True)])
        - (Fr(1, 8) - g / 3),
        "Σ b β α² − (1/12 − γ/3)": dot(b, times(strict, [x * x for x in alpha_sum])) - (Fr(1, 12) - g / 3),
        "Σ b β β β' − (1/24 − γ/2 + 3γ²/2 − γ³)": dot(b, times(strict, times(strict, beta_sum)))
        - (Fr(1, 24) - g / 2 + Fr(3, 2) * g * g - g**3),
    }


def largest_coefficient(parameters):
    a, c, m, gamma_i = transformed(*method(*parameters))
    values = a[3][:3] + [c[i][j] for i in range(4) for j in range(i)] + gamma_i
    return max(abs(x) for x in values), max(x.denominator for x in values)


def search():
    """Small fractions for (b₁, b₂, β₂₁), ranked by their largest transformed coefficient, then
    by the largest denominator."""
    fractions = sorted({Fr(p, q) for q in (1, 2, 3, 4, 6) for p in range(-6, 7)} - {Fr(0)})
    ranked = []
    for parameters in itertools.product(fractions, fractions, fractions):
        try:
            ranked.append((largest_coefficient(parameters), parameters))
        except (ZeroDivisionError, StopIteration):
            continue  # a singular choice
    ranked.sort(key=lambda r: r[0])
    return ranked[0][1]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="verify the chosen method, no search")
    args = parser.parse_args()
    parameters = CHOSEN if args.check else search()
    alpha, beta, b = method(*parameters)
    a, c, m, gamma_i = transformed(alpha, beta, b)
    conditions, order4 = checks(alpha, beta, b)
    print("(b₁, b₂, β₂₁) =", tuple(str(x) for x in parameters))
    below_diagonal = [[str(x) for x in row[:i]] for i, row in enumerate(beta)][1:]
    print("Hairer–Wanner form: α₄ =", [str(x) for x in alpha[3][:3]], " β =", below_diagonal, " b =", list(map(str, b)))
    c_named = {f"c{i + 1}{j + 1}": str(c[i][j]) for i in range(4) for j in range(i)}
    print("code's form: a₄ =", [str(x) for x in a[3][:3]], " c =", c_named)
    print("             m =", [str(x) for x in m], " γ_i =", [str(x) for x in gamma_i])
    for name, residual in conditions.items():
        print(f"  {name}: {residual}")
    print("order-4 residuals (fixed by the structure):")
    for name, residual in order4.items():
        print(f"  {name}: {residual}")
    failed = [name for name, residual in conditions.items() if residual != 0]
    if m != a[3][:3] + [Fr(1)]:
        failed.append("m = (a₄, 1)")
    if failed:
        raise SystemExit(f"derive_rosenbrock: conditions not met: {failed}")
    if args.check and parameters != CHOSEN:
        raise SystemExit("derive_rosenbrock: not the chosen method")


if __name__ == "__main__":
    main()
