"""A task defined outside the package, loaded by ``module:Class`` (it behaves as box
transfer with another instruction)."""

from __future__ import annotations

from typing import ClassVar

from workcell.tasks.box_transfer.task import BoxTransfer


class CarefulTransfer(BoxTransfer):
    name: ClassVar[str] = "careful_transfer"
    summary: ClassVar[str] = "box transfer, asked politely"

    def instruction(self, required: int) -> str:
        return f"Please carry {required} box(es) to the table, gently."


class NotATask:
    """Not a subclass of workcell.tasks.Task."""
