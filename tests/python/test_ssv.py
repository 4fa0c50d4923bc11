"""A parameter set written by `damper calibrate` (resources/calibrated.ssv) applied to the packaged
FMU as fmpy start values: every value reaches the FMU, and the calibrated gas pre-charge moves the
force at rest as the hydraulics say (F = -p_reservoir0 * A_rod at mid-stroke)."""

from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu

from damper_tools.ssv import read_ssv

CALIBRATED = Path(__file__).resolve().parent / "resources" / "calibrated.ssv"
REST_FORCE_REL_TOL = 0.02     # the rest force against -p_reservoir0 * A_rod (check-valve and spool terms)


def rest_force(fmu, start_values):
    """F_damper after 0.2 s at rest, valve at rest position (N)."""
    r = simulate_fmu(str(fmu), fmi_type="CoSimulation", stop_time=0.2, output_interval=1e-3,
                     start_values=start_values, output=["F_damper", "p_reservoir"])
    return float(r["F_damper"][-1]), float(r["p_reservoir"][-1])


def test_read_ssv_gives_typed_start_values(tmp_path):
    values = read_ssv(CALIBRATED)
    assert {"r_port", "air_fraction", "k1_mount", "p_reservoir0"} <= values.keys()
    assert all(isinstance(v, float) for v in values.values())
    bad = tmp_path / "bad.ssv"
    bad.write_text(CALIBRATED.read_text().replace('<ssv:Real value="', '<ssv:Real value="x', 1))
    with pytest.raises(ValueError, match="parameter r_port: bad value"):
        read_ssv(bad)


def test_calibrated_parameter_set_runs_in_the_fmu(fmu, model_description):
    values = read_ssv(CALIBRATED)
    names = {v.name for v in model_description.modelVariables}
    assert values.keys() <= names
    default_force, default_p = rest_force(fmu, {})
    force, p = rest_force(fmu, values)
    # the gas pre-charge is the rest pressure; the rest force scales with it
    assert p == pytest.approx(values["p_reservoir0"], rel=REST_FORCE_REL_TOL)
    assert force / default_force == pytest.approx(p / default_p, rel=REST_FORCE_REL_TOL)
    assert np.isfinite(force)
