#!/usr/bin/env python3
"""The command of damper_tools.roads (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/roads.py --help
"""

from damper_tools.roads import main

if __name__ == "__main__":
    main()
