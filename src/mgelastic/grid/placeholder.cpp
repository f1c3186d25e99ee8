// Placeholder until the grid engine's first files land.
