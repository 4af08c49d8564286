# BRDF Lobe Explorer: the page and its API. Stateless — run as many containers as you
# like behind any load balancer (docs/robustness.md).
#
#   docker build -t brdf-explorer . && docker run -p 8000:8000 brdf-explorer
#   docker run -p 8000:8000 -e BRDF_MAX_SECONDS=5 brdf-explorer \
#       brdf-explorer serve --host 0.0.0.0 --port 8000 --workers 2
FROM python:3.11-slim-bookworm

# Chromium renders the server-side SVG/PNG exports (kaleido finds it on PATH; without
# it those two formats answer 503 and everything else works).
RUN apt-get update \
 && apt-get install -y --no-install-recommends chromium \
 && rm -rf /var/lib/apt/lists/*

ENV PYTHONDONTWRITEBYTECODE=1 \
    PYTHONUNBUFFERED=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    NUMBA_CACHE_DIR=/tmp/numba-cache

WORKDIR /srv
COPY pyproject.toml setup.py README.md ./
COPY app ./app
COPY static ./static
# A regular install: the page ships inside the package (app/static). The user that runs
# the server cannot change what is installed; the compiled loops (app/kernels, numba)
# live in BRDF_KERNEL_DIR.
RUN pip install . && rm -rf /srv/* \
 && useradd --create-home --uid 10001 --shell /usr/sbin/nologin explorer
USER explorer
ENV BRDF_KERNEL_DIR=/home/explorer/kernels
# Compile the server's first models into the image (owned by the user that reads them):
# a container then loads them in seconds instead of compiling them in the background.
RUN python -c "from app import kernels; from app.main import default_loops; [kernels.compile_now(b, part) for b, part in default_loops()]"

EXPOSE 8000
# Healthy when /api/v1/health answers 200 within 2 s (urlopen raises on any other
# status or a timeout, which exits non-zero). start-period: imports and loading the compiled fast path.
HEALTHCHECK --interval=30s --timeout=5s --start-period=30s --retries=3 \
  CMD ["python", "-c", "import urllib.request as u; u.urlopen('http://127.0.0.1:8000/api/v1/health', timeout=2)"]
CMD ["brdf-explorer", "serve", "--host", "0.0.0.0", "--port", "8000"]
