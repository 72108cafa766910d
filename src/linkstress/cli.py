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
from linkstress.commands import HelpFormatter, examples
from linkstress.errors import InputError

COMMAND_MODULES = ("import_", "analyze", "validate", "sections", "regress", "bench")
"""In the order of the help's list: the main path (sketch, analysis, FEA check) first."""
COMMANDS = {name.removesuffix("_"): name for name in COMMAND_MODULES}
"""Each command's name and its module (``import`` lives in ``import_``: ``import`` is a Python keyword)."""
MAIN_PATH = (
    "linkstress import validation/cases/six_bar/six_bar.dxf --plot six_bar.png",
    "linkstress analyze validation/cases/six_bar/scene.toml --html six_bar.html",
    "linkstress validate validation/cases/six_bar/scene.toml --positions 4",
)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The command line's parser: with every command, or with ``command``'s alone (a command module
    imports what its command runs on, so a run imports its own module only)."""
    parser = argparse.ArgumentParser(
        prog="linkstress",
        description=(
            "Planar linkages from CAD sketches: kinematics, joint forces and section stresses, "
            "checked against plane-stress finite elements. SI units; angles in degrees where a "
            "name ends in _deg."
        ),
        epilog=examples(
            *MAIN_PATH,
            heading="example, the main path: a sketch's links, the analysis of the scene drawn from that sketch, "
            "and its check against FEA (paths from the root of a source checkout; each command's --help ends "
            "with examples of its own):",
        ),
        formatter_class=HelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"linkstress {__version__}")
    subparsers = parser.add_subparsers(title="commands", metavar="COMMAND")
    for name in [COMMANDS[command]] if command in COMMANDS else COMMAND_MODULES:
        importlib.import_module(f"linkstress.commands.{name}").register(subparsers)
    return parser


def main(argv: list[str] | None = None) -> int:
    if hasattr(signal, "SIGXFSZ"):
        # Past a file-size limit the kernel would kill the process mid-write; ignored, the write
        # fails with EFBIG instead and the output module reports it and leaves no file.
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    given = sys.argv[1:] if argv is None else argv
    parser = build_parser(given[0] if given else None)
    args = parser.parse_args(given)
    if not hasattr(args, "run"):
        parser.print_help()
        return 2
    try:
        from linkstress.threads import thread_limit

        thread_limit()  # a bad LINKSTRESS_THREADS stops the run before any work, by name
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
