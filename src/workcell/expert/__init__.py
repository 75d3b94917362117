"""The autonomous expert operator: a scripted demonstrator that emits Commands."""

from workcell.expert.operator import ExpertOperator
from workcell.expert.skill import ExpertConfig

__all__ = ["ExpertConfig", "ExpertOperator"]
