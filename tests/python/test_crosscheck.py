"""The packaged FMU against the damper's physics written again in plain Python (damper_tools.crosscheck):
scipy's Radau instead of the FMU's Rosenbrock method, the same parameters (the FMU's start values), the same input."""

from damper_tools.crosscheck import crosscheck

# Bound on the RMS difference of F_damper, FMU − Python, over 0.3 s (RMS force about 12.5 kN), with
# the FMU at rtol 1e-7 and scipy's Radau at 1e-7. Why 0.05 N (4e-6 of the RMS force), measured
# 2026-11-26 over these 0.3 s:
# - the two converge to each other: the FMU at rtol 1e-8 against Python at 1e-9 differ by 1.1e-4 N
#   RMS, so what is left at these tolerances is numerical error;
# - that error: the FMU at rtol 1e-7 is 1.0e-3 N RMS off (max 0.004 N), Python at 1e-7 1.6e-4 N;
#   this test measures 1.0e-3 N. The bound leaves 50x for other step-size sequences (a change of
#   the FMU's step control, another scipy). At rtol 1e-6 the FMU is 0.011 N off (max 0.043 N):
#   too near the bound;
# - a physics or controller difference shows far above it: in the Python model alone, +10 % on
#   p_transition (the orifice's regularisation, < 0.1 % on operating points) gives 0.087 N; +1 % on
#   Kd_x 1.9 N, on tau_coil 3.6 N, on air_fraction, k1_mount or Cv_valve 11-12 N, +0.1 % on K_sol
#   9 N; an amplifier delay one sample short 550 N.
# At the FMU's default rtol (3e-4) its own numerical error is 1.5 N RMS here (0.012 %, max 12 N at the
# relief valve; 9.0 N with Rodas3 at the earlier default 1e-3), which is why the test tightens it: at
# the default the check could not tell physics from numerics below a few newtons.
RMS_BOUND = 0.05  # N


def test_fmu_agrees_with_the_python_model(fmu):
    r = crosscheck(fmu, duration=0.3, rtol=1e-7, fmu_rtol=1e-7)
    assert r["rms_force"] > 5e3  # the input reaches the valve's working range (and the relief valve)
    assert r["rms_diff"] < RMS_BOUND, (
        f"F_damper differs by {r['rms_diff']:.3g} N RMS ({r['rms_diff_percent']:.2g} %), max {r['max_diff']:.3g} N")
