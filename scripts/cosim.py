#!/usr/bin/env python3
"""The command of damper_tools.cosim (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/cosim.py --help
"""

from damper_tools.cosim import main

if __name__ == "__main__":
    main()
