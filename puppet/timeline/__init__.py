"""Time lines of input on top of the Session: scripted performances, recorded logs,
their replay and expectations, the ghost, motion export."""
