"""Palletize: four boxes from the conveyor stacked on a pallet in a 2x2 pattern
(:mod:`workcell.tasks.palletize.task`)."""
