"""Reports of an analysis: JSON records, terminal text and self-contained HTML."""
