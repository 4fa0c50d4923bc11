"""ecos (ecospy 0.7.2, damper_tools.ecos), a third co-simulation master beside fmpy and libcosim.

The damper alone and the quarter truck + damper, built from the FMUs or loaded from the SSP that
damper-ssp writes, give fmpy's results bit for bit (tolerance 0): ecos calls the same binary with the
same doubles (inputs, parameters, communicationStepSize = h; its accumulated communication point is
not used in the FMUs' numerics), and both masters are Jacobi. Any coupling difference (one step more
or less of lag, an input set late or not at all, a parameter not applied) moves the force by newtons.

Each test runs on the FMI 2.0 FMUs and on their FMI 3.0 builds, which ecos loads too. The references
are always fmpy's runs of the FMI 2.0 FMUs: an FMI 3.0 build of the same model must give the same
numbers.
"""

import numpy as np
import pytest
from fmpy import read_model_description

from damper_tools import cosim, ecos, roads, ssp
from damper_tools.fmu import FmuUnit, Slave

DURATION = 2.0  # s
# 2^-9 s keeps ecos's accumulated time exact (t_k + h = (k + 1) h); at 1 ms it is rounded.
STEPS = [2.0**-9, 1e-3]
# The truck's outputs that depend on its state alone: ecos reads them as cosim.py does.
STATE_OUTPUTS = [n for n in cosim.TRUCK_OUTPUTS if n not in ("a_body", "a_axle", "F_suspension")]


@pytest.fixture(params=["FMI 2.0", "FMI 3.0"])
def ecos_fmus(request, fmus):
    """The FMUs ecos runs: the session's FMI 2.0 ones, or their FMI 3.0 builds."""
    if request.param == "FMI 2.0":
        return fmus
    fmi3 = {"truck_fmu": request.getfixturevalue("truck_fmu3"), "damper_fmu": request.getfixturevalue("fmu3")}
    for path in fmi3.values():
        assert read_model_description(str(path)).fmiVersion.startswith("3."), path
    return fmi3


def damper_inputs(step):
    """A velocity sine (extension and compression, 0.15 m/s) and a dissipative demand stepping between
    2 and 12 kN every 0.2 s, at t_k = k h."""
    n = round(DURATION / step)
    t = step * np.arange(n + 1)
    v = 0.15 * np.sin(2 * np.pi * 1.5 * t)
    f = (2e3 + 10e3 * (np.floor(t / 0.2) % 2)) * np.sign(v)
    return v, f, n


def fmpy_damper(fmu, v, f, step, n, **parameters):
    """fmpy's run of the damper: damper_tools.fmu's Slave, inputs set before the step from t_k = k h."""
    damper = Slave(FmuUnit.load(fmu), "damper")
    try:
        damper.initialize(0.0, n * step, **parameters)
        forces = [damper.get(["F_damper"])[0]]
        for k in range(n):
            damper.step(step, k * step, v_damper=v[k], F_demand=f[k])
            forces.append(damper.get(["F_damper"])[0])
    finally:
        damper.free()
    return np.array(forces)


def minor_road(step):
    case = roads.road_case("minor", 14.0, DURATION, 3, step=step)
    return case.z_road, case.v_road, case.t.size - 1


@pytest.mark.parametrize("step", STEPS)
def test_the_damper_alone_in_ecos_gives_fmpys_forces(ecos_fmus, fmu, step):
    v, f, n = damper_inputs(step)
    reference = fmpy_damper(fmu, v, f, step, n)
    assert reference[0] < -500 and np.sqrt(np.mean(reference**2)) > 5e3  # the untared gas force, then kN

    result = ecos.run_damper(v, f, step, n, ecos_fmus["damper_fmu"])

    assert np.array_equal(result["time"], step * np.arange(n + 1))
    assert np.array_equal(result["damper.F_damper"], reference)


def test_the_damper_in_a_process_of_its_own_gives_the_same_forces(ecos_fmus, fmu, tmp_path, monkeypatch):
    # ecos's proxyfmu program runs the instance; it needs the execute bit that scripts/setup.sh sets,
    # and writes its log to logs/ under the working directory (here a temporary one)
    monkeypatch.chdir(tmp_path)
    v, f, n = damper_inputs(1e-3)
    result = ecos.run_damper(v, f, 1e-3, n, ecos_fmus["damper_fmu"], {"tare_load_cell": True},
                             separate_processes=True)
    assert np.array_equal(result["damper.F_damper"], fmpy_damper(fmu, v, f, 1e-3, n, tare_load_cell=True))


@pytest.mark.parametrize("step", STEPS)
def test_the_quarter_truck_in_ecos_gives_the_fmpy_masters_results(ecos_fmus, fmus, step):
    z_road, v_road, n = minor_road(step)
    reference = cosim.simulate_one(z_road, v_road, step, n, **fmus)
    force = reference["damper.F_damper"]
    assert np.sqrt(np.mean(force**2)) > 1e3  # a real load: RMS force of kN

    result = ecos.run_quarter_truck(z_road, v_road, step, n, **ecos_fmus)

    assert np.array_equal(result["damper.F_damper"], force)
    for name in STATE_OUTPUTS:
        assert np.array_equal(result[f"truck.{name}"], reference[name]), name
    # ecos reads the outputs after the connections have set F_damper(t_k+1) on the truck, cosim.py
    # before: the outputs fed through from F_damper differ by the force's change over the step.
    # 1e-12 of their peak is rounding, with four orders of magnitude to spare.
    change = np.concatenate(([0.0], np.diff(force)))
    truck = FmuUnit.load(fmus["truck_fmu"]).parameters()
    for name, per_newton in [("F_suspension", 1.0), ("a_body", -1 / truck["m_body"]), ("a_axle", 1 / truck["m_axle"])]:
        shift = result[f"truck.{name}"] - reference[name]
        np.testing.assert_allclose(shift, per_newton * change, rtol=0, atol=1e-12 * np.max(np.abs(reference[name])),
                                   err_msg=name)


def test_ecos_runs_the_ssp_with_its_parameter_bindings(ecos_fmus, tmp_path):
    # the bindings set tare_load_cell = true: untared, the force would be 1 kN off
    ssp_file = ssp.write_ssp(tmp_path / "QuarterTruckHiL.ssp", **ecos_fmus)
    z_road, v_road, n = minor_road(1e-3)

    from_ssp = ecos.run_ssp(ssp_file, z_road, v_road, 1e-3, n)
    from_fmus = ecos.run_quarter_truck(z_road, v_road, 1e-3, n, **ecos_fmus)

    assert from_ssp.keys() == from_fmus.keys()
    for name, values in from_fmus.items():
        assert np.array_equal(from_ssp[name], values), name


def test_an_input_the_fmu_would_refuse_is_refused_before_the_run(ecos_fmus):
    # ecos ignores fmi2SetReal's status: the FMU would keep its last input and the run would go on
    v, f, n = damper_inputs(1e-3)
    v[100] = 6.0  # m/s; v_damper is declared in [-5, 5]
    with pytest.raises(ValueError, match=r"v_damper\[100\] = 6.0 is outside"):
        ecos.run_damper(v, f, 1e-3, n, ecos_fmus["damper_fmu"])
