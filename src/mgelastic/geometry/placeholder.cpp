// Placeholder until the geometry module's first files land.
