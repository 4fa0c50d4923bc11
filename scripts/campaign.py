#!/usr/bin/env python3
"""The command of damper_tools.campaign (`damper diagnose` over a folder of records on Dask; the
package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/campaign.py --help
"""

from damper_tools.campaign import main

if __name__ == "__main__":
    raise SystemExit(main())
