"""Physics: characters and scenes built from their specs into pymunk, stepped at a fixed rate."""
