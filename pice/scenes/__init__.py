"""Scene builders: turn a validated job into particles (its bodies and moorings: pice.platform.build)."""
