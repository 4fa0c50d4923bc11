"""The damper's integrator is the method scripts/derive_rosenbrock.py derives: the script's exact
check passes, and the coefficients it prints are the ones src/solver/rosenbrock.rs writes out."""

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_integrator_is_the_derived_method():
    derived = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "derive_rosenbrock.py"), "--check"],
        capture_output=True, text=True, check=True,
    ).stdout
    assert "code's form: a₄ = ['-3', '3', '1']" in derived
    assert "'c21': '3', 'c31': '0', 'c32': '-3/2', 'c41': '0', 'c42': '-3/2', 'c43': '3'" in derived
    assert "m = ['-3', '3', '1', '1']  γ_i = ['1/3', '2/3', '0', '0']" in derived
    source = (ROOT / "src" / "solver" / "rosenbrock.rs").read_text()
    for line in [
        "const GAMMA: f64 = 1.0 / 3.0;",
        "let u1 = lu.solve(&(f0 + f_t * (h / 3.0)));",
        "(u1, lu.solve(&(f0 + u1 * (3.0 / h) + f_t * (2.0 * h / 3.0))))",
        "(u1, lu.solve(&(f0 + u1 * (3.0 / h))))",
        "let u3 = lu.solve(&(f0 + u2 * (-1.5 / h)));",
        "let y4 = y + (u2 - u1) * 3.0 + u3;",
        "let u4 = lu.solve(&(rhs_at_end(&y4) + (u3 * 3.0 - u2 * 1.5) * (1.0 / h)));",
        "let y1 = y4 + u4;",
    ]:
        assert line in source, f"src/solver/rosenbrock.rs no longer has: {line}"
