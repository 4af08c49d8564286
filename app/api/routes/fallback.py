"""Any other ``/api/v1/{name}``: included last (app/main.py). A path that exists with
other methods is a 405 naming them; an unknown name a 404 listing the views."""
from fastapi import APIRouter, HTTPException

from ...views import lookup
from ..deps import OperationsDep, Route

router = APIRouter(prefix="/api/v1", route_class=Route)


@router.api_route("/{name}", methods=["GET", "POST"], include_in_schema=False)
def unknown(index: OperationsDep, name: str):
    """POST /api/v1/health is a 405 with Allow: GET; an unknown name is a 404 listing the
    views; a view's data route takes GET only."""
    item = index.exact.get(f"/api/v1/{name}", {})
    allowed = sorted(m.upper() for m in item if m in ("get", "post", "put", "delete"))
    if not allowed:
        lookup(name)
        allowed = ["GET"]
    raise HTTPException(405, "Method Not Allowed", headers={"Allow": ", ".join(allowed)})
