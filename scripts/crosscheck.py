#!/usr/bin/env python3
"""The command of damper_tools.crosscheck (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/crosscheck.py --help
"""

from damper_tools.crosscheck import main

if __name__ == "__main__":
    main()
