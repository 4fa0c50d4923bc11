"""Campaign diagnosis on Dask (damper_tools.campaign, damper-campaign, docs/sweeps.md): three
records, one with a hidden seal friction, one clean and one broken file, diagnosed by the `damper`
program as tasks of a real LocalCluster of two worker processes; one table with the right verdicts,
the broken file a row with its error, an index page linking every report, and a rerun that diagnoses
nothing again."""

import csv
import json

import pytest

from damper_tools import campaign


@pytest.fixture(scope="module")
def client(dask_client):
    return dask_client


@pytest.fixture(scope="module")
def records(damper, tmp_path_factory):
    """records/: a seal friction hidden (2 s), a clean record (2 s), a broken file; truth/ beside it."""
    root = tmp_path_factory.mktemp("campaign")
    for case in (campaign.GenCase("friction", ("seal_friction",), 3), campaign.GenCase("clean", (), 4)):
        campaign.generate(case, root / "records", root / "truth", duration=2.0, damper=damper)
    (root / "records" / "broken.csv").write_text("time,v_damper,F_demand,F_damper\n0,0.1,abc\n", encoding="utf-8")
    return root


def test_three_records_one_table(client, damper, records, tmp_path):
    out = tmp_path / "out"
    code = campaign.main(["--damper", str(damper), "diagnose", str(records / "records"), "--out", str(out),
                          "--truth", str(records / "truth"), "--scheduler", client.scheduler.address])
    assert code == 0
    with (out / "campaign.csv").open(encoding="utf-8") as f:
        rows = {r["record"]: r for r in csv.DictReader(f)}
    assert sorted(rows) == ["broken.csv", "clean.csv", "friction.csv"]

    friction, clean, broken = rows["friction.csv"], rows["clean.csv"], rows["broken.csv"]
    assert (friction["status"], friction["verdict"], friction["effects"], friction["right"]) == \
        ("ok", "effect", "seal_friction", "True")
    fitted = json.loads(friction["fitted_json"])
    truth = json.loads((records / "truth" / "friction.json").read_text(encoding="utf-8"))
    hidden = truth["effects"][0]["params"]["F_coulomb"]
    assert abs(fitted["F_coulomb"]["value"] - hidden) < 0.2 * hidden and fitted["F_coulomb"]["std_error"] > 0
    assert "F_coulomb=" in friction["fitted"] and "±" in friction["fitted"]
    assert float(friction["nrmse_after"]) < float(friction["nrmse_baseline"])
    assert (clean["status"], clean["verdict"], clean["effects"], clean["right"]) == ("ok", "none", "", "True")
    # the broken file is a row with its error, not the end of the campaign
    assert broken["status"] == "error" and broken["error"] and broken["verdict"] == "" and broken["report"] == ""

    page = (out / "index.html").read_text(encoding="utf-8")
    for name in ("friction", "clean"):
        assert f"href='reports/{name}/report.html'" in page
        assert (out / "reports" / name / "report.html").stat().st_size > 10_000
        assert json.loads((out / "reports" / name / "summary.json").read_text(encoding="utf-8"))["verdict"]
    assert "right verdicts: 2 of 2" in (out / "campaign.md").read_text(encoding="utf-8")

    # a rerun diagnoses only what failed
    again = campaign.run_campaign(campaign.find_records(records / "records"), out, client=client, damper=damper,
                                  truth_dir=records / "truth")
    assert (again.ran, again.skipped) == (1, 2)
    assert [r["verdict"] for r in again.rows] == [None, "none", "effect"]
