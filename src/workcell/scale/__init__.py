"""Generating data at scale: worker processes (or Ray tasks) writing store shards."""
