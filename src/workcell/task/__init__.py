"""The task: modes, trials, the timer, scoring and the events of every transition."""
