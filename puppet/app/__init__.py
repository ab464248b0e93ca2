"""Presentation: the pygame app (window loop, camera, rendering, HUD, key map, the
HUD's and key map's words in describe.py), headless frames, video export and the joint
plot. Nothing here changes the sim except through Session.handle, so a headless replay
sees exactly what the window did."""
