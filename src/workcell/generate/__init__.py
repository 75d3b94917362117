"""Demonstration generation: a few recorded source trials become many new ones in new
worlds (``workcell generate``, docs/generation.md).

Each source trial is cut at its task's recorded stage boundaries into segments, each
expressed relative to the object its arms act on (:mod:`workcell.generate.segments`); an
attempt draws a new world, moves every segment with its object's new pose
(:mod:`workcell.generate.planar`), and replays the source motion through the same
:class:`~workcell.control.command.Command` path as any operator
(:mod:`workcell.generate.operator`), recorded like any trial and re-checked a second after
its success (:mod:`workcell.generate.recheck`). The task's expert is never called.
"""
