"""A synchronous publish/subscribe channel for task events."""

from __future__ import annotations

from collections.abc import Callable

from workcell.task.events import TaskEvent

Subscriber = Callable[[TaskEvent], None]


class EventBus:
    """Hands each published event to every subscriber, in subscription order."""

    def __init__(self) -> None:
        self._subscribers: list[Subscriber] = []

    def subscribe(self, subscriber: Subscriber) -> Callable[[], None]:
        """Add ``subscriber``; returns a function that removes it again."""
        self._subscribers.append(subscriber)

        def unsubscribe() -> None:
            if subscriber in self._subscribers:
                self._subscribers.remove(subscriber)

        return unsubscribe

    def publish(self, event: TaskEvent) -> None:
        for subscriber in list(self._subscribers):
            subscriber(event)
