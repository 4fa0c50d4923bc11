#!/usr/bin/env python3
"""The command of damper_tools.sweep_report (a sweep file run on Dask; the package scripts/setup.sh
installs into .venv):

    .venv/bin/python scripts/sweep.py --help
"""

from damper_tools.sweep_report import main

if __name__ == "__main__":
    raise SystemExit(main())
