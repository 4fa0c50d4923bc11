#!/usr/bin/env python3
"""The command of damper_tools.ssp (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/ssp.py --help
"""

from damper_tools.ssp import main

if __name__ == "__main__":
    main()
