"""Sort: boxes of two kinds arrive on the conveyor in random order; each kind goes to its
own table (:mod:`workcell.tasks.sort.task`)."""
