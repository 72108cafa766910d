"""The ``linkstress`` command line.

Each subcommand lives in its own module under ``linkstress.commands`` with ``register(subparsers)``,
which adds its parser and sets ``run``, a function ``args -> exit code``. Exit codes: 0 success,
1 a validation or regression check failed, 2 bad input (one message, no traceback).
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys

from linkstress import __version__
from linkstress.errors import InputError

COMMAND_MODULES = ("sections", "analyze", "import_", "validate", "regress", "bench")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="linkstress",
        description=(
            "Planar linkages from CAD sketches: kinematics, joint forces and section stresses, "
            "checked against plane-stress finite elements. SI units; angles in degrees where a "
            "name ends in _deg."
        ),
    )
    parser.add_argument("--version", action="version", version=f"linkstress {__version__}")
    subparsers = parser.add_subparsers(title="commands", metavar="COMMAND")
    for name in COMMAND_MODULES:
        importlib.import_module(f"linkstress.commands.{name}").register(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    if hasattr(signal, "SIGXFSZ"):
        # Past a file-size limit the kernel would kill the process mid-write; ignored, the write
        # fails with EFBIG instead and the output module reports it and leaves no file.
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    parser = build_parser()
    args = parser.parse_args(argv)
    if not hasattr(args, "run"):
        parser.print_help()
        return 2
    try:
        return int(args.run(args))
    except InputError as error:
        print(f"linkstress: error: {error}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("linkstress: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # The reader (e.g. `| head`) left early. Point stdout at devnull so that the interpreter's
        # final flush does not fail again (the recipe of Python's signal module documentation).
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
