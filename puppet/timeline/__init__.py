"""Time lines of input: scripted performances, recorded logs, checkpoints, replay."""
