"""Motion capture: reading BVH clips (and writing planar ones)."""
