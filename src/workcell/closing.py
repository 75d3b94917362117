"""Objects that hold a resource (a file, a process, an OpenGL context) until closed, and
close it at the end of a ``with`` block."""

from __future__ import annotations

import abc
from types import TracebackType
from typing import Self


class Closing(abc.ABC):
    """``with obj:`` gives ``obj`` and calls :meth:`close` on the way out, whatever
    happened inside."""

    @abc.abstractmethod
    def close(self) -> None:
        """Release the resource; closing twice is harmless."""

    def __enter__(self) -> Self:
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        error: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self.close()
