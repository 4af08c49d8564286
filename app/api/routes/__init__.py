"""API v1's routers, one module per resource; app/main.py includes them in the order
FastAPI should try them (the most asked first)."""
