"""The ``novelty`` command line.

A session, each line as written, in an empty folder: simulate two runs along
the paper's corridor A, learn them with the paper's detector, score them
again with the saved model, plot the novelty along the route, and benchmark
two detectors on one seed::

    novelty list
    novelty simulate paper-a --runs 2 --out corridor-a.npz
    novelty run hsom --data corridor-a.npz --out novelty.csv --save hsom.npz
    novelty score --model hsom.npz --data corridor-a.npz --out rescored.csv
    novelty plot novelty.csv --out route.png
    novelty bench --detector hsom --detector lof --task paper-a-to-b --seeds 1 --out results/first

``novelty COMMAND --help`` gives the options and examples of each command.

Each command is one module of this package with two functions,
``add_parser(subparsers)`` and ``run(args) -> int``, listed in
:data:`COMMANDS`. Adding a command is adding a module and one line here;
for instance ``novelty/cli/score.py``, shortened::

    from ._common import add_command, add_data_options

    def add_parser(subparsers):
        parser = add_command(subparsers, "score", "score scans with a saved model (no learning)",
                             DESCRIPTION, ["novelty score --model hsom.npz --data corridor-a.npz --out rescored.csv"])
        parser.add_argument("--model", required=True, metavar="FILE", help="a saved detector (.npz)")
        add_data_options(parser)
        return parser

    def run(args) -> int:
        ...            # raise UserError("...") for anything the user can fix
        return 0

and ``"score": "novelty.cli.score"`` in :data:`COMMANDS`.
User errors (unknown names, bad parameters, missing or malformed files, bad
data) are printed as one line on stderr with exit code 2, never a traceback.
A closed output pipe (``novelty list | head``) ends the command quietly with
exit code 141, as a shell reports a command stopped by SIGPIPE.
"""

from __future__ import annotations

import importlib
import os
import sys
from typing import Sequence

from .._version import __version__
from ._common import NoveltyParser, one_line, user_errors

__all__ = ["main", "COMMANDS", "build_parser"]

#: command name -> module of this package that implements it, in --help order
COMMANDS = {
    "list": "novelty.cli.list_",
    "bench": "novelty.cli.bench",
    "run": "novelty.cli.run",
    "score": "novelty.cli.score",
    "node": "novelty.cli.node",
    "simulate": "novelty.cli.simulate",
    "plot": "novelty.cli.plot",
    "reproduce": "novelty.cli.reproduce",
}

#: the session of the module's docstring (tests/cli/test_init.py runs it)
_EPILOG = """examples:
  novelty list
  novelty simulate paper-a --runs 2 --out corridor-a.npz
  novelty run hsom --data corridor-a.npz --out novelty.csv --save hsom.npz
  novelty score --model hsom.npz --data corridor-a.npz --out rescored.csv
  novelty plot novelty.csv --out route.png
  novelty bench --detector hsom --detector lof --task paper-a-to-b --seeds 1 --out results/first

run 'novelty COMMAND --help' for the options and examples of each command."""


def build_parser() -> NoveltyParser:
    parser = NoveltyParser(
        prog="novelty",
        description="Habituation-based novelty detection: list components, benchmark detectors, "
        "run and score detectors on scans, simulate sonar corridors.",
        epilog=_EPILOG,
    )
    parser.add_argument("--version", action="version", version=f"novelty {__version__}")
    parser.add_argument("--traceback", action="store_true",
                        help="show the full traceback of an unexpected error (for bug reports)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=NoveltyParser)
    for name, module in COMMANDS.items():
        command = importlib.import_module(module)
        command.add_parser(sub).set_defaults(_run=command.run, _command=name)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``novelty`` command line; return the exit code."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:  # --help, --version, or a usage error already printed
        return exc.code if isinstance(exc.code, int) else 0
    args._argv = list(sys.argv[1:] if argv is None else argv)  # recorded by commands that keep provenance
    if getattr(args, "_run", None) is None:
        parser.print_help(sys.stderr)
        return 2
    prog = f"novelty {args._command}"
    try:
        code = int(args._run(args) or 0)
        sys.stdout.flush()  # a closed pipe is found here, not in Python's flush at exit
        return code
    except BrokenPipeError:
        return _output_closed()
    except user_errors() as exc:
        print(f"{prog}: error: {one_line(exc)}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"{prog}: interrupted.", file=sys.stderr)
        return 130
    except Exception as exc:  # noqa: BLE001 - a bug: one line unless asked for details
        if args.traceback:
            raise
        print(f"{prog}: internal error: {type(exc).__name__}: {one_line(exc)} "
              "(rerun with 'novelty --traceback ...' and report it)", file=sys.stderr)
        return 1


#: exit code of a command whose reader closed the pipe (128 + SIGPIPE, as a shell reports it)
EXIT_PIPE_CLOSED = 141


def _output_closed() -> int:
    """The reader of standard output went away (``novelty list | head``): stop quietly.

    What is still buffered for standard output goes to the null device, so that
    Python's flush at exit does not report the broken pipe either.
    """
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (AttributeError, OSError, ValueError):  # not a real file (a test's capture)
        pass
    return EXIT_PIPE_CLOSED


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
