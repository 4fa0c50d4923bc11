"""Sweeps on Dask (damper_tools.sweep, damper-sweep, docs/sweeps.md), on a real LocalCluster of
two worker processes: the cluster gives bit for bit the rows of a serial run in this process, a
worker killed in the middle of a sweep is survived, a rerun skips the finished points, and the
command writes the Parquet table, the plots and the page."""

import json
import os
import signal

import numpy as np
import pandas as pd
import pytest

from damper_tools import REPO, sweep, sweep_report

TINY = REPO / "sweeps" / "tiny.toml"


@pytest.fixture(scope="module")
def client(dask_client):
    return dask_client


@pytest.fixture(scope="module")
def paths(fmus):
    return {"truck": fmus["truck_fmu"], "damper": fmus["damper_fmu"]}


@pytest.fixture(scope="module")
def serial(paths, tmp_path_factory):
    """The tiny sweep run serially in this process: the reference."""
    spec = sweep.load(TINY)
    outcome = sweep.run_sweep(spec, tmp_path_factory.mktemp("serial"), paths)
    return sweep.table(spec, outcome.rows)


def assert_same_bits(a: pd.DataFrame, b: pd.DataFrame) -> None:
    """Every column but the wall time equal; the float columns equal bit for bit (NaN included)."""
    a, b = a.drop(columns="wall_s"), b.drop(columns="wall_s")
    assert list(a.columns) == list(b.columns)
    pd.testing.assert_frame_equal(a, b, check_exact=True)
    for c in a.columns:
        if a[c].dtype == np.float64:
            assert a[c].to_numpy().tobytes() == b[c].to_numpy().tobytes(), c


def test_serial_run_is_a_table_of_every_input_and_metric(serial):
    spec = sweep.load(TINY)
    assert len(serial) == 8 and (serial["error"] == "").all()
    for col in ["road", "Cm", "alpha", "speed", "duration", *sweep.HIL_METRICS]:
        assert col in serial
    assert serial[list(sweep.HIL_METRICS)].notna().all().all()
    # one road realisation per road: every damper setting on it gets the same run seed
    assert serial.groupby("road")["run_seed"].nunique().eq(1).all()
    assert serial["run_seed"].nunique() == 2
    # the stronger skyhook gain lowers the DLC on both roads
    by = serial.groupby(["road", "Cm"])["DLC"].mean().unstack()
    assert (by[24e3] < by[12e3]).all()
    assert sweep.points(spec) == sweep.points(sweep.load(TINY))


def test_two_workers_give_the_serial_rows_bit_for_bit(client, paths, serial, tmp_path):
    spec = sweep.load(TINY)
    outcome = sweep.run_sweep(spec, tmp_path, paths, client=client)
    assert outcome.ran == 8 and outcome.failed == 0
    assert_same_bits(sweep.table(spec, outcome.rows), serial)


def test_a_killed_worker_is_survived(client, paths, tmp_path):
    """A worker process is killed (SIGKILL) as the first result arrives, while the other points run:
    its task is run again elsewhere and every row arrives, equal to a serial run."""
    spec = sweep.from_dict({"name": "kill", "scenario": "hil", "seed": 5,
                            "fixed": {"road": "minor", "speed": 14.0, "duration": 2.0, "settle": 0.5},
                            "grid": {"Cm": [8e3, 12e3, 16e3, 20e3, 24e3, 28e3], "alpha": [0.5, 0.9]}})
    before = client.run(os.getpid)
    killed, in_flight = [], []

    def kill_one(row):
        if not killed:
            processing = client.processing()
            busy = [w for w, keys in processing.items() if keys]
            assert busy, "no task running: the sweep ended before the kill"
            in_flight.extend(processing[busy[0]])
            killed.append(before[busy[0]])
            os.kill(killed[0], signal.SIGKILL)

    outcome = sweep.run_sweep(spec, tmp_path / "cluster", paths, client=client, on_result=kill_one)
    assert killed and killed[0] not in client.run(os.getpid).values()  # the nanny started a new process
    assert any(str(k).startswith("sweep-kill-") for k in in_flight)
    assert len(outcome.rows) == 12 and outcome.failed == 0
    reference = sweep.run_sweep(spec, tmp_path / "serial", paths)
    assert_same_bits(sweep.table(spec, outcome.rows), sweep.table(spec, reference.rows))
    client.wait_for_workers(2, timeout=60)


def test_a_rerun_skips_the_finished_points(client, paths, serial, tmp_path):
    spec = sweep.load(TINY)
    # an interrupted run: 3 points finished
    first = sweep.run_sweep(spec, tmp_path, paths, client=client, limit=3)
    assert first.ran == 3 and len(first.rows) == 3
    done = {p: p.stat().st_mtime_ns for p in (tmp_path / "points").glob("*.json")}
    assert len(done) == 3
    second = sweep.run_sweep(spec, tmp_path, paths, client=client)
    assert (second.ran, second.skipped) == (5, 3)
    assert all(p.stat().st_mtime_ns == t for p, t in done.items())  # not run again
    # a lost result is run again, alone
    lost = sorted(tmp_path.glob("points/*.json"))[0]
    lost.unlink()
    third = sweep.run_sweep(spec, tmp_path, paths, client=client)
    assert (third.ran, third.skipped) == (1, 7)
    assert_same_bits(sweep.table(spec, third.rows), serial)


def test_the_command_writes_parquet_plots_and_page(client, fmus, serial, tmp_path):
    out = tmp_path / "out"
    code = sweep_report.main([str(TINY), "--scheduler", client.scheduler.address, "--out", str(out), "--quiet",
                              "--truck-fmu", str(fmus["truck_fmu"]), "--damper-fmu", str(fmus["damper_fmu"])])
    assert code == 0
    table = pd.read_parquet(out / "results.parquet")
    assert_same_bits(table, serial)
    for name in ("tradeoff.png", "heatmap_a_body_rms_Cm_alpha.png", "sensitivity.png"):
        assert (out / "plots" / name).stat().st_size > 10_000, name
    page = (out / "index.html").read_text(encoding="utf-8")
    assert "plots/tradeoff.png" in page and "results.parquet" in page
    sens = pd.read_csv(out / "sensitivity.csv")
    assert set(sens["parameter"]) == {"road", "Cm", "alpha"}
    run = json.loads((out / "run.json").read_text(encoding="utf-8"))
    assert run["workers"] == 2 and run["ran"] == 8
    # run again: nothing is run, the same table
    assert sweep_report.main([str(TINY), "--serial", "--out", str(out), "--quiet", "--no-plots",
                              "--truck-fmu", str(fmus["truck_fmu"]), "--damper-fmu", str(fmus["damper_fmu"])]) == 0
    assert json.loads((out / "run.json").read_text(encoding="utf-8"))["ran"] == 0
    assert_same_bits(pd.read_parquet(out / "results.parquet"), serial)


def test_a_bad_sweep_is_refused_or_reported(paths, tmp_path):
    with pytest.raises(sweep.SweepError, match="scenario"):
        sweep.from_dict({"scenario": "boat", "seed": 1})
    bad = tmp_path / "bad.toml"
    bad.write_text('scenario = "hil"\nseed = 1\n[grid]\nCm = []\n', encoding="utf-8")
    with pytest.raises(sweep.SweepError, match="empty"):
        sweep.load(bad)
    spec = sweep.from_dict({"scenario": "hil", "seed": 1, "fixed": {"duration": 0.5, "settle": 0.2},
                            "grid": {"no_such_parameter": [1.0]}})
    row = sweep.run_sweep(spec, tmp_path / "w", paths).rows[0]
    assert "no_such_parameter" in row["error"] and np.isnan(row["a_body_rms"])
    assert not list((tmp_path / "w" / "points").glob("*.json"))  # not kept: a rerun tries it again


def test_the_full_truck_and_rig_scenarios(paths, full_truck_fmu, tmp_path):
    truck = sweep.from_dict({"scenario": "full_truck", "seed": 3, "fixed": {"duration": 1.0, "settle": 0.5},
                             "grid": {"Cm": [12e3, 24e3]}})
    rows = sweep.run_sweep(truck, tmp_path / "truck", {**paths, "truck": full_truck_fmu}).rows
    assert all(not r["error"] and 0 < r["DLC"] <= r["DLC_max"] for r in rows)
    assert rows[1]["DLC"] < rows[0]["DLC"]  # the stronger skyhook gain holds the road better
    rig = sweep.from_dict({"scenario": "rig", "seed": 3, "grid": {"air_fraction": [0.01, 0.04]}})
    low, high = sweep.run_sweep(rig, tmp_path / "rig", paths).rows
    for r in (low, high):  # the paper's bands (docs/rig-validation.md): 15-35 ms, compression slower
        assert not r["error"] and 0.015 < r["extension_t90"] < 0.035 and r["compression_to_extension_t90"] > 1
    assert high["compression_t90"] > low["compression_t90"]  # more air, a softer oil column
