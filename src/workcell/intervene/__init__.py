"""A person corrects a running autonomous driver: take-over and hand-back (issue 35)."""
