"""Python tools around the FMUs of this repository (SemiActiveDamper.fmu, QuarterTruck.fmu, FullTruck.fmu).

Modules: `fmu` (one FMU instance through fmpy's FMU2Slave), `cosim` (the Jacobi master), `roads`
(ISO 8608 and OpenCRG road inputs), `ssp` (the SSP of the coupled system, run with fmpy.ssp and
libcosim), `rig_tests` and `paper_tests` (the paper's rig tests), `valve_response` (valve and force-loop
transfer functions, flow map), `hil_scenarios` (the HiL runs), `hil_rig` (the HiL rig as a model),
`full_truck` (the three-axle truck with six dampers), `instances` (six quarter trucks in one
master), `ride`, `tracking_quality` and `benefit_map` (the semi-active benefit), `sweep` and
`sweep_report` (sweeps on Dask), `campaign` (`damper diagnose` over a folder on Dask) and `verdicts`
(the diagnosis verdicts and the one rule of a right one, for the scorers). The
commands .venv/bin/damper-* (pyproject.toml's [project.scripts]) run their `main`.
"""

import math
import os
from collections.abc import Collection
from pathlib import Path
from typing import Any

import numpy as np
import numpy.typing as npt

# The arrays the package passes around (time series, road samples, results): float64 throughout.
FloatArray = npt.NDArray[np.float64]
# A table as a numpy structured array, one float64 field per column (fmpy.simulate_fmu's inputs and
# results, a road CSV as roads.read_road_csv reads it).
Records = npt.NDArray[np.void]


def _repository() -> Path:
    """The source checkout the commands work in: the FMUs are built under its target/, the outputs go
    to its out/ and the road data are in its data/. DAMPER_REPO (an environment variable) names it;
    without it, the checkout the package is installed from (scripts/setup.sh's editable install:
    python/damper_tools/ in it); for a package installed elsewhere (a wheel in site-packages), the
    current directory."""
    named = os.environ.get("DAMPER_REPO")
    if named:
        return Path(named).resolve()
    checkout = Path(__file__).resolve().parents[2]
    if (checkout / "pyproject.toml").is_file() and (checkout / "python" / "damper_tools").is_dir():
        return checkout
    return Path.cwd()


REPO = _repository()
# The FMUs as the packaging commands write them (scripts/package_fmu.py, package_truck.py,
# package_full_truck.py): every command's default.
FMU_DIR = REPO / "target" / "fmu"
DAMPER_FMU = FMU_DIR / "SemiActiveDamper.fmu"
TRUCK_FMU = FMU_DIR / "QuarterTruck.fmu"
FULL_TRUCK_FMU = FMU_DIR / "FullTruck.fmu"
# The `damper` program as `cargo build --release -p damper_cli` writes it.
DAMPER = REPO / "target" / "release" / "damper"


def jsonable(x: Any, drop: Collection[str] = ()) -> Any:
    """`x` (dicts, lists, tuples, floats, numpy scalars) as plain JSON values for a results.json: NaN
    becomes null and an infinity the string "inf" or "-inf" (JSON has neither); dict keys in `drop`
    are left out at every depth."""
    if isinstance(x, dict):
        return {k: jsonable(v, drop) for k, v in x.items() if k not in drop}
    if isinstance(x, (list, tuple)):
        return [jsonable(v, drop) for v in x]
    if isinstance(x, np.generic):
        x = x.item()
    if isinstance(x, float) and not math.isfinite(x):
        return None if math.isnan(x) else ("inf" if x > 0 else "-inf")
    return x


def pyplot() -> Any:
    """matplotlib.pyplot on the Agg backend: the plots are files, no display is needed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt
