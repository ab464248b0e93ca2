"""The pygame app: window loop, camera, rendering, HUD. Nothing here changes the sim
except through Session.handle, so a headless replay sees exactly what the window did."""
