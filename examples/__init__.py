"""Examples of Workcell's extension points (each folder complete on its own; docs/tasks.md)."""
