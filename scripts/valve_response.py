#!/usr/bin/env python3
"""The command of damper_tools.valve_response (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/valve_response.py --help
"""

from damper_tools.valve_response import main

if __name__ == "__main__":
    main()
