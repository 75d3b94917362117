"""What a command module of the ``workcell`` command line provides (see
:mod:`workcell.cli.main`, which lists them): ``register(subparsers)`` and ``run(args)``."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Protocol, TypeAlias

Subparsers: TypeAlias = "argparse._SubParsersAction[argparse.ArgumentParser]"
RunFunc: TypeAlias = Callable[[argparse.Namespace], int]


class CommandModule(Protocol):
    """What a command module provides (modules satisfy this protocol structurally)."""

    def register(self, subparsers: Subparsers) -> None: ...

    def run(self, args: argparse.Namespace) -> int: ...
