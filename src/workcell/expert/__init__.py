"""The scripted demonstrators' shared parts: their skill (:class:`ExpertConfig`), phases and
grasp geometry. The carrying expert the tasks build from is
:class:`workcell.tasks.elements.expert.ExpertOperator`; each task names its own."""

from workcell.expert.skill import ExpertConfig

__all__ = ["ExpertConfig"]
