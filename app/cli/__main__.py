"""``python -m app.cli``: the same as ``brdf-explorer``."""
from . import main

raise SystemExit(main())
