"""How a generation is going: attempts, acceptance with its Wilson interval, false
successes, why attempts were rejected, and the cost."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field

from workcell.generate.attempts import AttemptResult
from workcell.metrics.statistics import wilson_interval


@dataclass
class Tally:
    """The attempts so far."""

    attempts: int = 0
    accepted: int = 0
    false_successes: int = 0
    cpu_s: float = 0.0
    rejected_at: Counter[str] = field(default_factory=Counter)
    """Rejected attempts by outcome and stage reached (``timeout at lifted``)."""

    def add(self, result: AttemptResult) -> None:
        self.attempts += 1
        self.accepted += result.accepted
        self.false_successes += result.false_success
        self.cpu_s += result.cpu_s
        if not result.accepted:
            key = "false success" if result.false_success else f"{result.outcome} at {result.stage}"
            self.rejected_at[key] += 1

    def rate(self) -> str:
        """``a/n accepted = p % (Wilson 95 % lo-hi %)``."""
        if not self.attempts:
            return "no attempts"
        low, high = wilson_interval(self.accepted, self.attempts)
        share = 100 * self.accepted / self.attempts
        return (
            f"{self.accepted}/{self.attempts} accepted = {share:.1f}% "
            f"(Wilson 95 % {100 * low:.1f}-{100 * high:.1f}%)"
        )

    def per_cpu_hour(self) -> float:
        """Attempts per CPU-hour of the processes that ran them."""
        return 3600 * self.attempts / self.cpu_s if self.cpu_s > 0 else float("nan")

    def rejections(self) -> str:
        if not self.rejected_at:
            return "none"
        return ", ".join(f"{n} {why}" for why, n in self.rejected_at.most_common())
