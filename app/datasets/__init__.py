"""Data sets a user brings: measured or computed BRDF values and single terms, read from
MERL .binary and CSV files, kept in a bounded store, summarised, and written back out."""
