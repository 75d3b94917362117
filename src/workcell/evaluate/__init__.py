"""``workcell evaluate``: one operator's rollouts in a task's named worlds, on seeds that
every operator evaluated so shares, recorded like any session and read back as the
generalization ladder (:mod:`workcell.audit.ladder`)."""
