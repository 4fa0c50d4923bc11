#!/usr/bin/env python3
"""The command of damper_tools.paper_tests (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/paper_tests.py --help
"""

from damper_tools.paper_tests import main

if __name__ == "__main__":
    main()
