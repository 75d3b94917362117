"""Shelve: a box from the table onto the shelf the instruction names
(:mod:`workcell.tasks.shelve.task`). Deliberately empty: the stages
(:mod:`workcell.tasks.shelve.stages`) read without loading the simulation."""
