"""The ``neuromesh`` command that ``pip install`` gives.

It is the Rust command line itself (the same code as the ``neuromesh``
binary that ``cargo install`` builds), run in this process: same flags,
output and exit codes.
"""

from __future__ import annotations

import sys

from . import _native


def main() -> None:
    """Runs ``neuromesh`` with this process's arguments and exits with its code."""
    sys.exit(_native._run_cli(["neuromesh", *sys.argv[1:]], True))


if __name__ == "__main__":
    main()
