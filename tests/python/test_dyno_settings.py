"""An adjustable damper on the dyno at three settings of one bleed adjuster, calibrated in one go
as its user would: the records of an independent model (damper_tools.dyno, short programs), the
datasheet, `damper calibrate --per-setting` with the records grouped by the test log book's
settings. The adjuster's value per setting comes out near the truth, within its reported
uncertainty, and every record near its noise floor. About 15 s on 2 cores.
"""

import json
import subprocess

from damper_tools import dyno
from damper_tools.dyno_score import settings_arguments


def test_three_settings_of_an_adjuster_calibrate_together(damper, tmp_path):
    records = dyno.make_records("car", 1, "settings", tmp_path / "records", quick=True)
    sheet = tmp_path / "records" / "car_1_datasheet.toml"
    changes = [json.loads(r.with_suffix(".json").read_text())["change"] for r in records]
    assert [c["setting"] for c in changes] == ["middle", "middle", "closed", "open"]
    adjuster = changes[0]["parameter"]

    out = tmp_path / "cal"
    done = subprocess.run([str(damper), "calibrate", *map(str, records), "--damper", str(sheet), "--out", str(out),
                           "--threads", "2", *settings_arguments(records)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert f"{adjuster}[closed]" in done.stdout, done.stdout

    c = json.loads((out / "calibration.json").read_text())
    assert c["settings"] == ["middle", "closed", "open"]
    own = {p["setting"]: p for p in c["parameters"] if p["setting"]}
    assert set(own) == {"middle", "closed", "open"}
    for setting, p in own.items():
        truth = changes[0]["values"][setting]
        assert p["name"] == adjuster and p["status"] == "fitted"
        assert abs(p["value"] - truth) <= 0.02 * truth, (setting, p["value"], truth)
        assert abs(p["value"] - truth) <= 3 * p["std_uncertainty"], (setting, p["value"], truth, p["std_uncertainty"])
    assert not any(p["name"] == adjuster for p in c["parameters"] if not p["setting"])
    for r in c["records"]:
        assert r["nrmse_after"] <= 2.0 * r["noise_floor"], r  # the bar (measured: 1.06-1.45)
    for setting in own:
        assert (out / f"parameters_{setting}.ssv").is_file()
