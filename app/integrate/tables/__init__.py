"""E(μ, α) tables of a single-scattering lobe: ``table.py`` (one table: its grid, build
and error), ``store.py`` (whole tables kept, persisted and built outside requests; imports
table, never the reverse), ``defaults.py`` (the tables a server queues at start-up) and
``lookup.py`` (which table answers a lobe). The names other packages use are these."""
from .lookup import compensation_table, table_for, table_for_key, tabulated_albedo
from .table import ETable, TableTooSlow, build, mu_from_y, table_key, y_from_mu

__all__ = ["ETable", "TableTooSlow", "build", "compensation_table", "mu_from_y", "table_for", "table_for_key", "table_key",
           "tabulated_albedo", "y_from_mu"]
