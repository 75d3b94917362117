"""The autonomous expert operator: a scripted demonstrator that emits Commands."""

from workcell.expert.operator import ExpertConfig, ExpertOperator

__all__ = ["ExpertConfig", "ExpertOperator"]
