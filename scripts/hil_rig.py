#!/usr/bin/env python3
"""The command of damper_tools.hil_rig (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/hil_rig.py --help
"""

from damper_tools.hil_rig import main

if __name__ == "__main__":
    main()
