# The image installs and starts the service with the README's own commands (make run), as the user synth, who
# owns /app; the store lives on the volume /data:
#   docker run -d -p 127.0.0.1:8000:8000 -v mechsynth-data:/data mechsynth
FROM python:3.11-slim
RUN apt-get update && apt-get install -y --no-install-recommends make \
    && rm -rf /var/lib/apt/lists/* \
    && useradd --create-home --uid 1000 synth \
    && mkdir -p /app /data && chown synth:synth /app /data
WORKDIR /app
COPY --chown=synth:synth . /app
USER synth
# The service alone: the package without its test extra (pytest, hypothesis, mypy, schemathesis stay out).
ENV EXTRAS=""
RUN make .venv/.installed
ENV HOST=0.0.0.0 PORT=8000 MPLBACKEND=Agg SYNTH_STUDIES_DB=/data/synth-studies.sqlite
VOLUME ["/data"]
EXPOSE 8000
HEALTHCHECK --interval=30s --timeout=5s --start-period=20s --retries=3 \
    CMD .venv/bin/python -c "import urllib.request,sys; sys.exit(urllib.request.urlopen('http://127.0.0.1:8000/health').status != 200)"
CMD ["make", "run", "HOST=0.0.0.0"]
