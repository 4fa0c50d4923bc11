#!/usr/bin/env python3
"""The command of damper_tools.blind_score (the package scripts/setup.sh installs into .venv):

    .venv/bin/python scripts/blind_score.py --quick
    .venv/bin/python scripts/blind_score.py --help
"""

from damper_tools.blind_score import main

if __name__ == "__main__":
    raise SystemExit(main())
