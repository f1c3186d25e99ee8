// Placeholder until the io module's first files land.
