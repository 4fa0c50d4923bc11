"""The compiled coupled run (damper_tools.runner over crates/cosim_runner) against the fmpy loop it
replaces in the sweeps (damper_tools.cosim, the reference): the same road fed as a series gives the
same numbers bit for bit; the truck's own ISO 8608 road (road_source = 1) gives roads.road_case's road
to the inverse FFT's rounding, and the runs agree to what that rounding grows into; refusals, bad jobs
and a road too short end with the FMU's or the job's reason; threads do not change a bit."""

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest

from damper_tools import cosim, roads, runner, sweep
from damper_tools.fmu import FmuUnit

STEP = 1e-3
DURATION = 3.0
# The truck's own road against roads.road_case's: the profiles differ by the inverse FFT's rounding
# (pocketfft against crates/suspension/src/fft.rs: up to 1.9e-14 of max|z|, below);
# the runs grow it by the coupled dynamics. Measured: F_damper within 3e-13 of its RMS over 15 s,
# a_body 2e-13, F_tyre 1e-12. The bound leaves three decades for other inputs and seeds, and is still
# ten decades below any physical effect (a 1e-3 change in a parameter moves them by 1e-4 or more).
OWN_ROAD_REL = 1e-9


@pytest.fixture(scope="module")
def library(runner_library):
    return runner_library


@pytest.fixture(scope="module")
def case():
    return roads.road_case("minor", 14.0, DURATION, 5, step=STEP)


def reference(case, fmus, truck_parameters=None):
    n = case.z_road.size - 1
    return cosim.simulate_one(case.z_road, case.v_road, STEP, n, cosim.MODE_EXTERNAL, truck_parameters or {},
                              cosim.HIL_DAMPER_PARAMETERS, **fmus)


def test_the_road_fed_as_a_series_gives_the_fmpy_loop_bit_for_bit(library, case, fmus):
    ref = reference(case, fmus)
    n = case.z_road.size - 1
    fed = runner.run_quarter_truck({}, STEP, n, road=(case.z_road, case.v_road), **fmus)
    assert np.std(ref["damper.F_damper"]) > 1e3  # a real load, kN
    for name in ("time", *cosim.TRUCK_OUTPUTS, "damper.F_damper", "z_road", "v_road"):
        assert np.array_equal(fed[name], ref[name]), name


def test_the_trucks_own_road_is_road_case_to_rounding(library, case, fmus):
    ref = reference(case, fmus)
    n = case.z_road.size - 1
    params = runner.own_road("minor", 14.0, DURATION, seed=5, step=STEP)
    out = runner.run((("truck", fmus["truck_fmu"], params),), STEP, n, (("truck", "z_road"), ("truck", "v_road")))
    z, v = out[:, 0], out[:, 1]
    # after step k the truck holds z_road(t_k) + v_road h, z_road(t_{k+1}) on the chord. The two
    # inverse FFTs of this 2151-sample profile (3·3·239: pocketfft's prime factor, our Bluestein)
    # differ by up to 1.9e-14 of max|z| (measured), and v_road = Δz/h by 3.6e-13 of max|v|.
    assert np.max(np.abs(z[1:] - case.z_road[1:])) < 1e-13 * np.max(np.abs(case.z_road))
    assert np.max(np.abs(v[1:] - case.v_road[:-1])) < 2e-12 * np.max(np.abs(case.v_road))
    own = runner.run_quarter_truck(params, STEP, n, **fmus)
    for name in ("damper.F_damper", "a_body", "F_tyre", "x_damper", "F_demand"):
        scale = np.std(ref[name])
        assert np.max(np.abs(own[name] - ref[name])) < OWN_ROAD_REL * scale, name
    assert not np.array_equal(own["damper.F_damper"], ref["damper.F_damper"]), "two roads, not one"


def test_a_refused_step_ends_the_run_with_the_fmus_reason(library, case, fmus):
    # a road too short for the run: the truck refuses the step that would leave it
    params = {**runner.own_road("minor", 14.0, DURATION, seed=5, step=STEP), "road_length": 14.0}
    with pytest.raises(cosim.Refused) as refused:
        runner.run_quarter_truck(params, STEP, case.z_road.size - 1, **fmus)
    assert refused.value.instance == "truck"
    assert "raise road_length" in refused.value.message
    assert 0.9 < refused.value.time < 1.1  # 14 m + 1 m at 14 m/s: about 1.07 s


def test_an_unstable_truck_is_refused_as_in_the_fmpy_loop(library, case, fmus):
    # RK4 with 10 ms substeps on a 500 MN/m tyre (h_max·ω ≈ 11 > 2.5): the truck refuses to initialise
    bad = {"h_max": 0.01, "k_tyre": 5e8}
    with pytest.raises(cosim.Refused) as fmpy:
        reference(case, fmus, bad)
    with pytest.raises(cosim.Refused) as ours:
        runner.run_quarter_truck(bad, STEP, case.z_road.size - 1, road=(case.z_road, case.v_road), **fmus)
    assert fmpy.value.message in ours.value.message
    assert ours.value.instance == fmpy.value.instance.split(".")[-1] == "truck"


def test_a_bad_job_names_the_variable(library, fmus):
    with pytest.raises(ValueError, match=r"truck\.no_such_output: not a variable"):
        runner.run((("truck", fmus["truck_fmu"], {}),), STEP, 10, (("truck", "no_such_output"),))
    with pytest.raises(ValueError, match=r"road_sauce: no such variable"):
        runner.run((("truck", fmus["truck_fmu"], {"road_sauce": 1}),), STEP, 10, (("truck", "a_body"),))
    with pytest.raises(ValueError, match=r"2 samples, 10 needed"):
        runner.run((("truck", fmus["truck_fmu"], {}),), STEP, 10, (("truck", "a_body"),),
                   inputs={("truck", "z_road"): np.zeros(2)})


def test_runs_on_threads_give_the_same_bits(library, fmus):
    params = [runner.own_road("major", 20.0, 1.0, seed=s, step=STEP) for s in (1, 2, 3, 1, 2, 3)]
    alone = [runner.run_quarter_truck(p, STEP, 1000, **fmus)["damper.F_damper"] for p in params[:3]]
    with ThreadPoolExecutor(3) as pool:
        together = list(pool.map(lambda p: runner.run_quarter_truck(p, STEP, 1000, **fmus)["damper.F_damper"], params))
    for k, f in enumerate(together):
        assert np.array_equal(f, alone[k % 3]), k
    assert not np.array_equal(alone[0], alone[1])


def sweep_point(**settings):
    return {"speed": 14.0, "duration": 1.0, "settle": 0.5, "fade_in": 0.3, "Cm": 24e3, "alpha": 0.8, **settings}


def test_a_sweep_point_gives_the_fmpy_loops_metrics(library, fmus):
    """Same metrics, the road made by the truck: equal to the fmpy loop's within OWN_ROAD_REL (the
    fitted delays and bandwidths exactly)."""
    fmu_paths = (fmus["truck_fmu"], fmus["damper_fmu"])
    ours = sweep.run_hil(sweep_point(road="minor"), 9, *fmu_paths)
    ref = sweep.run_hil(sweep_point(road="minor", master="fmpy"), 9, *fmu_paths)
    assert set(ours) == set(ref) == set(sweep.HIL_METRICS)
    for name in sweep.HIL_METRICS:
        if name.startswith(("tracking_delay", "tracking_bandwidth")):
            assert ours[name] == ref[name], name
        else:
            assert abs(ours[name] - ref[name]) <= OWN_ROAD_REL * abs(ref[name]), name


def test_a_fed_road_gives_the_fmpy_loops_metrics_bit_for_bit(library, fmus):
    fmu_paths = (fmus["truck_fmu"], fmus["damper_fmu"])
    ours = sweep.run_hil(sweep_point(road=sweep.CRG_ROAD, mode="ideal"), 1, *fmu_paths)
    ref = sweep.run_hil(sweep_point(road=sweep.CRG_ROAD, mode="ideal", master="fmpy"), 1, *fmu_paths)
    assert ours == pytest.approx(ref, rel=0, abs=0, nan_ok=True)


def test_the_self_contained_ssp_runs_in_libcosim_and_ecos_with_nothing_fed(library, fmus, tmp_path):
    """The SSP whose truck makes its own road has no inputs: libcosim and ecos run it to stop time
    with no Python feeding them, and give the runner's forces bit for bit (at 2^-9 s every master's
    communication points are exact)."""
    from xml.etree import ElementTree as ET

    from damper_tools import ecos, ssp

    step, n = 2.0 ** -9, 1024
    tp = {**ssp.DEFAULT_TRUCK_PARAMETERS, **runner.own_road("minor", 14.0, n * step, 3, step=step)}
    path = ssp.write_ssp(tmp_path / "own_road.ssp", fmus["truck_fmu"], fmus["damper_fmu"], truck_parameters=tp)
    system = ET.fromstring(ssp.zipfile.ZipFile(path).read("SystemStructure.ssd")).find(f"{{{ssp.SSD}}}System")
    assert system is not None and system.find(f"{{{ssp.SSD}}}Connectors") is None, "no system inputs"
    ref = runner.run_quarter_truck(tp, step, n, **fmus)["damper.F_damper"]
    assert np.std(ref) > 1e3
    assert np.array_equal(ssp.run_libcosim(path, None, None, step, n)["damper.F_damper"][1:], ref[1:])
    assert np.array_equal(ecos.run_ssp(path, None, None, step, n)["damper.F_damper"], ref)


def test_the_full_truck_gives_the_fmpy_loops_numbers_bit_for_bit(library, fmu, full_truck_fmu):
    from damper_tools import full_truck

    p = full_truck.parameters(FmuUnit.load(full_truck_fmu))
    wheels, n, _ = full_truck.case_roads(full_truck.Case("minor", 14.0), p, 0.6, 0.2, STEP, 4, 0.6)
    args = (wheels, STEP, n, {}, None)
    ref = full_truck.simulate(*args, full_truck_fmu=full_truck_fmu, damper_fmu=fmu)
    ours = runner.run_full_truck(*args, full_truck_fmu=full_truck_fmu, damper_fmu=fmu)
    assert set(ours) == set(ref)
    for name in ref:
        assert np.array_equal(ours[name], ref[name]), name
    assert np.std(ref["front_left.damper.F_damper"]) > 100
