"""Studies: many participants, each running the study's conditions in a counterbalanced
order (a study file, its validation and template, each participant's plan of sessions,
and what a store says they have done)."""
