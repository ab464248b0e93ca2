"""puppet: drive physically simulated planar characters in real time.

Data flow, one direction per step:
input devices -> interface runtime -> PD targets -> physics step -> render / record.
"""

__version__ = "0.2.0"
