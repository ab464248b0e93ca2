"""Input sources: everything that sends input events to a Session.

One door: every source hands plain event dicts (``puppet.interface.events``) to
``Session.handle``, which records them and passes them to the interface runtime, at
the step the simulation is at. What differs is only *when* a source's events arrive:

* devices (``puppet.app.devices``: keys, mouse, gamepads) are translated from pygame's
  events in the window's frame loop;
* scripts and logs (``puppet.timeline.script``, ``puppet.session.playback``) carry the
  step each event acts at, and are played by ``playback.play``;
* live sources on other threads (a motion-capture stream, a network plugin) post into
  a ``LiveQueue`` (``puppet.input.live``), which the frame loop drains once a frame, so
  that the simulation stays single-threaded and a recording of a live take replays
  bit-identically.
"""
