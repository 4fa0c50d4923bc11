#!/usr/bin/env python3
"""The command of damper_tools.hil_scenarios (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/hil_scenarios.py --help
"""

from damper_tools.hil_scenarios import main

if __name__ == "__main__":
    main()
