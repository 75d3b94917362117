"""The ``workcell`` command line: one module per command, listed once in :data:`COMMANDS`.

A command module exposes ``register(subparsers)``, which adds its parser and sets
``func=run`` on it, and ``run(args) -> int``. Command modules import MuJoCo and other heavy
dependencies inside ``run`` only, so that ``--help`` stays fast. (MuJoCo chooses its OpenGL
backend from ``MUJOCO_GL`` on first import; importing :mod:`workcell` sets it to ``egl``
unless already set.)
"""

from __future__ import annotations

import argparse
import re
import sys
from collections.abc import Sequence
from typing import NoReturn, cast

from workcell import __version__
from workcell.cli import (
    annotate,
    audit,
    collect,
    config,
    demo,
    evaluate,
    export,
    generate,
    merge,
    render,
    serve,
    snapshot,
    study,
    tasks,
    train,
    verify,
)
from workcell.cli.closed_output import EXIT_OUTPUT_CLOSED, discard_stdout, reader_gone
from workcell.cli.command import CommandModule, RunFunc, Subparsers
from workcell.errors import ConfigError, WorkcellError, shown

__all__ = ["COMMANDS", "EXIT_INTERRUPTED", "EXIT_USAGE", "PROG", "Subparsers", "main"]

PROG = "workcell"
EXIT_USAGE = 2
"""Exit status for bad input and every other WorkcellError."""
EXIT_INTERRUPTED = 130

COMMANDS: tuple[CommandModule, ...] = (
    collect,
    audit,
    annotate,
    config,
    demo,
    evaluate,
    export,
    generate,
    merge,
    render,
    serve,
    snapshot,
    study,
    tasks,
    train,
    verify,
)
"""Every command of the command line, in help order."""


class UsageError(WorkcellError):
    """The command line itself was malformed (unknown option, missing argument, ...)."""


class _Parser(argparse.ArgumentParser):
    """An argument parser that reports bad input as one line instead of usage + exit."""

    def error(self, message: str) -> NoReturn:
        # argparse quotes the value it refused whole: cut one of thousands of characters
        message = re.sub(r"'[^']{100,}'", lambda long: shown(long[0][1:-1]), message)
        raise UsageError(f"{message} (see '{self.prog} --help')")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog=PROG,
        description="Simulated factory workcell with a mobile bimanual robot.",
    )
    parser.add_argument("--version", action="version", version=f"{PROG} {__version__}")
    # Subcommand parsers are _Parser too (argparse uses the parent's class).
    subparsers = cast(
        Subparsers, parser.add_subparsers(title="commands", dest="command", required=True)
    )
    for command in COMMANDS:
        command.register(subparsers)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line with ``argv`` (default ``sys.argv[1:]``); returns the exit status."""
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
        run: RunFunc = args.func
        return run(args)
    except SystemExit as done:  # --help and --version print, then exit 0
        return done.code if isinstance(done.code, int) else 0 if done.code is None else 1
    except ConfigError as error:
        for problem in error.problems:
            _print_error(problem)
        return EXIT_USAGE
    except WorkcellError as error:
        _print_error(str(error))
        return EXIT_USAGE
    except KeyboardInterrupt:
        _print_error("interrupted")
        return EXIT_INTERRUPTED
    except BrokenPipeError:
        if not reader_gone(sys.stdout):
            raise  # another pipe: a fault, not the reader of the output going away
        discard_stdout()
        return EXIT_OUTPUT_CLOSED


def _print_error(message: str) -> None:
    for line in message.splitlines() or [""]:
        print(f"{PROG}: error: {line}", file=sys.stderr)
