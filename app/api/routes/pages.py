"""The pages and their files: the explorer (``/``), ``/docs`` (Swagger UI from installed
files), ``/gallery`` and its entries (``GET /api/v1/gallery``), ``/embed/{view}`` (the
figure alone, for an iframe), the favicon and the installed plotly.js."""
from fastapi import APIRouter
from fastapi.responses import FileResponse
from starlette.concurrency import run_in_threadpool

from ... import gallery, server
from ...views import lookup
from ..deps import Route, StaticDirDep
from ..encode import json_response

router = APIRouter(route_class=Route)

#: plotly.js of the installed plotly package: the page works offline, and the figure
#: JSON always matches the plotly.js that draws it
PLOTLY_JS = server.plotly_js()
_HTML = {200: {"content": {"text/html": {"example": "<!doctype html><html lang=\"en\">…</html>"}}}}


@router.get("/", include_in_schema=False)
def index(static: StaticDirDep):
    return FileResponse(static / "index.html", media_type="text/html")


@router.get("/docs", include_in_schema=False)
def docs(static: StaticDirDep):
    return FileResponse(static / "docs.html", media_type="text/html")


@router.get("/favicon.ico", include_in_schema=False)
def favicon(static: StaticDirDep):
    return FileResponse(static / "favicon.svg", media_type="image/svg+xml")


@router.get("/static/vendor/plotly.min.js", include_in_schema=False)
def plotly_js():
    return FileResponse(PLOTLY_JS, media_type="application/javascript")


@router.get("/api/v1/gallery", tags=["meta"], summary="The gallery's figures, with captions and links",
            responses={200: {"content": {"application/json": {"example": [{
                "id": "ndf-tails", "title": "NDF tails at matched α", "kind": "ndf",
                "caption": "…", "state": {"alpha": 0.3, "vary": "ndf", "values": "ggx,beckmann"},
                "explorer": "/?alpha=0.3&vary=ndf&values=ggx%2Cbeckmann&show=ndf",
                "svg": "/api/v1/figures/ndf.svg?alpha=0.3&vary=ndf&values=ggx%2Cbeckmann"}]}}}})
async def gallery_entries():
    return json_response(await run_in_threadpool(gallery.available))


@router.get("/embed/{kind}", tags=["pages"], response_class=FileResponse, responses=_HTML,
            summary="The figure alone, sized to its iframe (controls=1 adds its sliders)",
            description="Example: `<iframe src=\"/embed/lobe?alpha=0.2&theta_i_deg=60\" "
                        "width=\"640\" height=\"420\"></iframe>`. Takes the figure's query "
                        "parameters; `controls=1` adds the sliders that matter for this "
                        "figure, `buttons=0` hides the export buttons.")
def embed(static: StaticDirDep, kind: str):
    lookup(kind)                             # 404 naming the views there are
    return FileResponse(static / "embed.html", media_type="text/html")


@router.get("/gallery", tags=["pages"], response_class=FileResponse, responses=_HTML,
            summary="Canonical figures with captions, each a link into the explorer")
def gallery_page(static: StaticDirDep):
    return FileResponse(static / "gallery.html", media_type="text/html")


@router.get("/tools", tags=["pages"], response_class=FileResponse, responses=_HTML,
            summary="The shader tools and the LUT workbench for the explorer's model")
def tools_page(static: StaticDirDep):
    return FileResponse(static / "tools.html", media_type="text/html")
