"""The interface runtime: turns input events into PD targets and gains."""
