"""Box transfer, the paper's task (:mod:`workcell.tasks.box_transfer.task`). Deliberately
empty: the audit reads the stages (:mod:`workcell.tasks.box_transfer.stages`) without
loading the simulation the task's judge and expert need."""
