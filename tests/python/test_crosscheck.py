"""The packaged FMU against the damper's physics written again in plain Python (damper_tools.crosscheck):
scipy's Radau instead of Rodas3, the same parameters (the FMU's start values), the same input."""

from damper_tools.crosscheck import crosscheck

# Bound on the RMS difference of F_damper, FMU − Python, over 0.3 s (RMS force about 12.5 kN), with
# the FMU at rtol 1e-6 and scipy's Radau at 1e-7. Why 0.05 N (4e-6 of the RMS force):
# - the two converge to each other: FMU at rtol 1e-8 against Python at 1e-9 differ by 1.5e-5 N RMS
#   over 1 s, so what is left at these tolerances is numerical error;
# - that error, measured: the FMU at rtol 1e-6 is 1.3e-3 N RMS off its rtol-1e-8 run (1 s), Python at
#   1e-7 is 1e-4 N off its 1e-9 run; this test measured 1.6e-3 N (max 0.019 N). The bound leaves 30x
#   for other step-size sequences (a change of the FMU's step control, another scipy);
# - a physics or controller difference shows far above it: in the Python model alone, +10 % on
#   p_transition (the orifice's regularisation, < 0.1 % on operating points) gives 0.087 N; +1 % on
#   Kd_x 1.9 N, on tau_coil 3.6 N, on air_fraction, k1_mount or Cv_valve 11-12 N, +0.1 % on K_sol
#   9 N; an amplifier delay one sample short 550 N.
# At the FMU's default rtol (1e-3) its own numerical error is about 1.2 N RMS here (0.01 %), which is
# why the test tightens it: at 1e-3 the check could not tell physics from numerics below 1 N.
RMS_BOUND = 0.05  # N


def test_fmu_agrees_with_the_python_model(fmu):
    r = crosscheck(fmu, duration=0.3, rtol=1e-7, fmu_rtol=1e-6)
    assert r["rms_force"] > 5e3  # the input reaches the valve's working range (and the relief valve)
    assert r["rms_diff"] < RMS_BOUND, (
        f"F_damper differs by {r['rms_diff']:.3g} N RMS ({r['rms_diff_percent']:.2g} %), max {r['max_diff']:.3g} N")
