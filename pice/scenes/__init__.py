"""Scene builders: turn a validated job into particles (and, later, bodies and moorings)."""
