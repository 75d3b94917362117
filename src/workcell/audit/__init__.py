"""Audit: recompute every metric from frames, flag quality problems, decide which trials
are valid (paper Fig. 4) and write the report (docs/architecture.md "audit/")."""
