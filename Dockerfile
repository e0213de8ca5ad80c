# rt: one image for the server, the Dask scheduler and the workers.
# Stage 1 builds the renderer (rtrender, rtcore, generated proto code) once;
# stage 2 builds the viewer; stage 3 is the runtime with only what they need.
#
# The base images are build arguments: the registry's by default, local ones
# where no registry is reachable (tests/compose builds them with debootstrap).
ARG DEBIAN_IMAGE=debian:bookworm
ARG DEBIAN_SLIM_IMAGE=debian:bookworm-slim
ARG NODE_IMAGE=node:20-bookworm-slim

FROM ${DEBIAN_IMAGE} AS renderer
RUN apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
      cmake ninja-build g++ pkg-config python3 python3-venv python3-dev \
      libopenimageio-dev libglm-dev libtinygltf-dev libtinyobjloader-dev libstb-dev libwebp-dev nlohmann-json3-dev \
      libdraco-dev libmeshoptimizer-dev \
      libprotobuf-dev protobuf-compiler libgtest-dev \
    && rm -rf /var/lib/apt/lists/*
WORKDIR /src
COPY requirements.txt .
# pyoidn brings Open Image Denoise, which the renderer loads from the venv; its
# CPU device is all a CPU image needs (the GPU devices and SYCL are 120 MB).
RUN python3 -m venv /opt/venv && /opt/venv/bin/pip install --no-cache-dir -r requirements.txt \
    && cd /opt/venv/lib/python3*/site-packages/pyoidn/oidn \
    && rm -rf bin lib/libOpenImageDenoise_device_cuda* lib/libOpenImageDenoise_device_hip* \
      lib/libOpenImageDenoise_device_sycl* lib/libsycl* lib/libur_* lib/libumf*
COPY proto proto
COPY renderer renderer
# Portable code: the image may run on another CPU than the one that built it.
RUN cmake -S renderer -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DRT_BENCH=OFF \
      -DPython_EXECUTABLE=/opt/venv/bin/python -DRT_RUNTIME_DIR=/src/build \
    && cmake --build build --target rtrender rtcore rt_proto_python

FROM ${NODE_IMAGE} AS web
# protoc's well-known types (google/protobuf/descriptor.proto, which
# proto/rt/options.proto imports) come with libprotobuf-dev.
RUN apt-get update && apt-get install -y --no-install-recommends protobuf-compiler libprotobuf-dev \
    && rm -rf /var/lib/apt/lists/*
WORKDIR /src
COPY proto proto
COPY docs/charts docs/charts
COPY web/package.json web/package-lock.json web/
RUN cd web && npm ci
COPY web web
RUN cd web && npm run build

FROM ${DEBIAN_SLIM_IMAGE}
RUN apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends \
      python3 libopenimageio2.4 libprotobuf32 libwebp7 libdraco7 libmeshoptimizer2d \
    && rm -rf /var/lib/apt/lists/*
COPY --from=renderer /opt/venv /opt/venv
COPY --from=renderer /src/build/rtrender /usr/local/bin/rtrender
COPY --from=renderer /src/build/python /opt/rt/python
COPY --from=web /src/web/dist /opt/rt/web
COPY server /opt/rt/server
ENV PATH=/opt/venv/bin:$PATH \
    PYTHONPATH=/opt/rt/server:/opt/rt/python \
    RT_WEB_DIR=/opt/rt/web \
    RT_DATA_DIR=/data \
    HOST=0.0.0.0 \
    PORT=8000
VOLUME /data
EXPOSE 8000
CMD ["python", "-m", "app"]
