// Placeholder until the tet engine's first files land.
