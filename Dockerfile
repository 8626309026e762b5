# Firefly in a container: an ArduCopter-compatible SITL vehicle on TCP 5760, as ArduPilot SITL's
# SERIAL0. Build and run (docs/container.md):
#   docker build -t firefly-sitl .
#   docker run --rm -p 5760:5760 firefly-sitl                 # then: mavproxy.py --master tcp:127.0.0.1:5760
#   docker run --rm -p 5760:5760 firefly-sitl --speedup 10 --home=-35.3632,149.1652,584,90
# The wheel is built with gcc in a first stage (the compiled control cascade and battery step), so
# the image that runs holds Python, the wheel and its dependencies only.
FROM python:3.11-slim AS build
RUN apt-get update && apt-get install -y --no-install-recommends gcc libc6-dev \
    && rm -rf /var/lib/apt/lists/*
WORKDIR /src
COPY . .
RUN CI=true pip wheel --no-cache-dir --no-deps --wheel-dir /wheels .

FROM python:3.11-slim
COPY --from=build /wheels /wheels
RUN pip install --no-cache-dir /wheels/*.whl && rm -rf /wheels
# Parameters, missions and logs persist here: mount a volume to keep them between containers.
VOLUME /var/lib/firefly
EXPOSE 5760/tcp
# In a container the vehicle's own loopback reaches nobody: clients come in on TCP (published
# with -p), and a UDP ground station can be named with --out udp:HOST:PORT after the image name.
ENTRYPOINT ["autopilot", "--serial0", "tcp:0.0.0.0:5760", "--state-dir", "/var/lib/firefly"]
CMD ["--speedup", "1"]
