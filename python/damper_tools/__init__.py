"""Python tools around the two FMUs of this repository (SemiActiveDamper.fmu, QuarterTruck.fmu).

Modules: `fmu` (one FMU instance through fmpy's FMU2Slave), `cosim` (the Jacobi master), `roads`
(ISO 8608 and OpenCRG road inputs), `ssp` (the SSP of the coupled system, run with fmpy.ssp and
libcosim), `rig_tests` and `paper_tests` (the paper's rig tests), `valve_response` (valve and force-loop
transfer functions, flow map), `hil_scenarios` (the HiL runs), `hil_rig` (the HiL rig as a model),
`full_truck` (six dampers as a three-axle truck), `sweep` and `sweep_report` (sweeps on Dask) and
`campaign` (`damper diagnose` over a folder on Dask). The commands in scripts/ run their `main`.
"""

from pathlib import Path

# The repository the package is installed from (editable install): the FMUs are built under its
# target/, the outputs go to its out/ and the road data are in its data/.
REPO = Path(__file__).resolve().parents[2]
