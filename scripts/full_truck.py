#!/usr/bin/env python3
"""The command of damper_tools.full_truck (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/full_truck.py --help
"""

from damper_tools.full_truck import main

if __name__ == "__main__":
    main()
