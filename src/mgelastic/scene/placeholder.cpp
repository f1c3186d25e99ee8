// Placeholder until the scene module's first files land.
