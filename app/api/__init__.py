"""HTTP layer: routes, query schemas, error handling, JSON encoding. No math here."""
