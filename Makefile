# Entry points: `make run` and `make test` set up everything they need on a fresh
# Debian machine (apt packages when missing, a venv at .venv, npm packages).
SHELL := /bin/bash
.DEFAULT_GOAL := help

BUILD   := build
VENV    := .venv
PY      := $(VENV)/bin/python
JOBS    ?= $(shell nproc)
SCENES  := $(BUILD)/scenes
# The per-feature glTFs of docs/gltf.md and the product-like model (tests only).
ASSETS  := $(BUILD)/assets

APT_PACKAGES := cmake ninja-build g++ ccache pkg-config git python3 python3-venv python3-dev \
  libopenimageio-dev libglm-dev libtinygltf-dev libtinyobjloader-dev libstb-dev libwebp-dev \
  libdraco-dev libmeshoptimizer-dev nlohmann-json3-dev libprotobuf-dev protobuf-compiler libgtest-dev libembree-dev \
  clang libclang-rt-14-dev qemu-user binutils

CMAKE_FLAGS := -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython_EXECUTABLE=$(abspath $(PY)) \
  -DRT_RUNTIME_DIR=$(abspath $(BUILD))
export CCACHE_DIR ?= $(HOME)/.cache/ccache
# Seconds each loader fuzz target runs: in `make test` (and `make fuzz`), and in `make bench`.
FUZZ_SECONDS ?= 15
BENCH_FUZZ_SECONDS ?= 300
# Requests schemathesis makes per API operation and phase: in `make test` (15), and in `make bench`.
BENCH_API_EXAMPLES ?= 300
# Seconds bvh_bench times each side of each figure for, on 1 thread and on all
# (its own default, 0.2, is for quick runs): longer windows leave this shared
# machine's slow spells a smaller part of each.
BENCH_BVH_SECONDS ?= 0.5

.PHONY: help deps venv build build-asan build-fuzz samples web test test-cpp test-asan fuzz test-py test-web test-compose run bench chaos charts clean

help:
	@echo "make run    serve the app on http://127.0.0.1:8000 (HOST, PORT override)"
	@echo "make test   build everything and run every test"
	@echo "make build  build the renderer, rtrender and rtcore"
	@echo "make bench  benchmarks: BVH against Embree, the 2020 report's performance table, the service against rtrender"
	@echo "make test-compose  build the image and run docker-compose.yml under podman (not in make test)"
	@echo "make fuzz   the loaders' libFuzzer targets, FUZZ_SECONDS each (crashes kept in build/fuzz/crashes)"
	@echo "make chaos  worker kills and a scheduler restart during batches, in the multi-process topology (~2 min)"
	@echo "make charts speed against accuracy, stability and scaling charts into docs/charts (on a quiet machine)"

# apt packages, installed only when missing.
$(BUILD)/.deps: Makefile
	@mkdir -p $(BUILD)
	@missing=$$(for p in $(APT_PACKAGES); do dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "ok installed" || echo $$p; done); \
	if [ -n "$$missing" ]; then \
	  echo "Installing apt packages:" $$missing; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null; \
	fi
	@# Node may come from elsewhere than Debian (its npm then conflicts with Debian's).
	@command -v npm >/dev/null || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq nodejs npm >/dev/null; }
	@touch $@
deps: $(BUILD)/.deps

$(VENV)/.stamp: requirements.txt $(BUILD)/.deps
	@test -x $(PY) || python3 -m venv $(VENV)
	$(PY) -m pip install -q --disable-pip-version-check -r requirements.txt
	@touch $@
venv: $(VENV)/.stamp

# One CMake tree builds the library, rtrender, the tests, rtcore and the
# benchmark; .venv sees rtcore and the generated proto code through a .pth file.
build: $(VENV)/.stamp
	@test -f $(BUILD)/renderer/build.ninja || cmake -S renderer -B $(BUILD)/renderer $(CMAKE_FLAGS) >/dev/null
	cmake --build $(BUILD)/renderer -j $(JOBS)
	@echo "$(abspath $(BUILD)/renderer/python)" > $$($(PY) -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')/rtcore.pth

# The loader and intersection tests again under AddressSanitizer + UBSan.
build-asan: $(VENV)/.stamp
	@test -f $(BUILD)/asan/build.ninja || cmake -S renderer -B $(BUILD)/asan -G Ninja -DCMAKE_BUILD_TYPE=Debug \
	  -DRT_SANITIZE=ON -DRT_PYTHON=OFF -DRT_BENCH=OFF >/dev/null
	cmake --build $(BUILD)/asan -j $(JOBS) --target rt_tests

# The loaders' libFuzzer targets (renderer/fuzz), built by clang with ASan+UBSan
# in a tree of their own, reused when present.
build-fuzz: $(BUILD)/.deps
	@test -f $(BUILD)/fuzz/build.ninja || cmake -S renderer -B $(BUILD)/fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ \
	  -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS_DEBUG="-O1 -gline-tables-only" -DRT_FUZZ=ON -DRT_PYTHON=OFF -DRT_BENCH=OFF >/dev/null
	cmake --build $(BUILD)/fuzz -j $(JOBS) --target fuzzers

samples: $(VENV)/.stamp
	$(PY) renderer/samples/make_samples.py --out $(SCENES)
	$(PY) renderer/samples/make_assets.py --out $(ASSETS)
	$(PY) renderer/samples/compressed.py --scenes $(SCENES) --out $(ASSETS)

test-cpp: build samples
	cd $(BUILD)/renderer && ctest --output-on-failure -j $(JOBS)

# Suites by name prefix: the loaders (Loader*), ray intersection (Triangle,
# Sphere*, Spawn, Bvh, WideBvh, Accel: every SIMD path), ProtoLimits and Stability*. The BVH's brute-force
# comparisons on the large sample meshes (10,000 rays against every triangle)
# stay in the release run.
test-asan: build-asan samples
	cd $(BUILD)/asan && ASAN_OPTIONS=detect_leaks=1 ctest --output-on-failure -j $(JOBS) \
	  -R '^(Loader|Triangle|Sphere|Spawn|Bvh|WideBvh|Accel|ProtoLimits|Stability|HugePages)' -E '^Bvh\.MatchesBruteForceOn(Dragon|Bunny)'

# Each fuzz target for FUZZ_SECONDS on the corpus it grew so far, seeded with
# the hostile corpus and the small sample scenes. A crash, sanitizer report,
# leak or timeout fails; the input stays in build/fuzz/crashes/.
fuzz: build-fuzz samples
	$(PY) renderer/fuzz/make_corpus.py --seeds $(BUILD)/fuzz/seeds --samples $(SCENES)
	$(PY) renderer/fuzz/run_fuzz.py --build $(BUILD)/fuzz --seeds $(BUILD)/fuzz/seeds --seconds $(FUZZ_SECONDS) --jobs $(JOBS)

test-py: build samples
	$(PY) -m pytest -q tests --ignore=tests/compose

# The Dockerfile and docker-compose.yml under podman, with base images made
# locally (no registry needed): tests/compose/test_compose.py installs podman
# when missing. Not part of `make test`: a cold run builds the image (long).
test-compose: build samples
	$(PY) -m pytest -q tests/compose

# The viewer (web/): npm packages when node_modules is missing or older than the
# lockfile; web/dist rebuilt (proto code generated first) unless it is newer than
# every source of it.
web: $(BUILD)/.deps
	@if [ ! -d web/node_modules ] || [ web/package-lock.json -nt web/node_modules ]; then \
	  (cd web && npm ci --no-audit --no-fund) && touch web/node_modules; \
	fi
	@if [ ! -f web/dist/index.html ] || [ -n "$$(find web/src web/scripts web/index.html web/vite.config.js \
	    web/package.json web/package-lock.json web/charts.html proto/rt docs/charts -newer web/dist/index.html -not -path 'web/src/gen/*' \
	    -type f 2>/dev/null | head -1)" ]; then \
	  cd web && npm run build; \
	else echo "web/dist is up to date"; fi

# The viewer in headless Debian chromium (installed when missing) against a
# server the tests start on a free port; screenshots in test-artifacts/web/.
test-web: build samples web
	@test -x /usr/bin/chromium || { echo "Installing chromium"; apt-get update -qq && \
	  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; }
	node --test --test-reporter=spec tests/web/

test: test-cpp test-asan fuzz test-py test-web

# The job service on http://$${HOST:-127.0.0.1}:$${PORT:-8000} with the sample scenes ready.
run: build samples web
	RT_SAMPLES_DIR=$(abspath $(SCENES)) PYTHONPATH=server $(PY) -m app

bench: build samples
	$(BUILD)/renderer/bvh_bench --scenes $(SCENES) --min-seconds $(BENCH_BVH_SECONDS)
	$(PY) renderer/bench/report_table.py --scenes $(SCENES) --rtrender $(BUILD)/rtrender --out $(BUILD)/bench
	$(PY) tests/bench/service_bench.py --scenes $(SCENES) --rtrender $(BUILD)/rtrender
	$(PY) renderer/bench/alpha_cost.py --assets $(ASSETS) --rtrender $(BUILD)/rtrender
	$(PY) renderer/bench/motion_cost.py --scenes $(SCENES) --rtrender $(BUILD)/rtrender
	$(PY) renderer/bench/instancing_cost.py --scenes $(SCENES) --rtrender $(BUILD)/rtrender
	$(PY) renderer/bench/instancing_cost.py --scenes $(SCENES) --rtrender $(BUILD)/rtrender --moving --spp 4
	$(PY) renderer/bench/product_memory.py
	$(PY) tests/bench/compressed_load_bench.py --scenes $(SCENES) --out $(BUILD)/bench
	$(MAKE) --no-print-directory fuzz FUZZ_SECONDS=$(BENCH_FUZZ_SECONDS)
	RT_FUZZ_EXAMPLES=$(BENCH_API_EXAMPLES) $(PY) -m pytest -q tests/server/test_api_contract.py -k schemathesis
	$(PY) tests/bench/load_bench.py --scenes $(SCENES) --clients 50 --jobs 20

# Chaos in the real multi-process topology (tests/chaos/chaos_cluster.py): 10
# worker kills during a batch of 20 jobs, with and without a shared data folder,
# and a scheduler restart mid-batch; prints its figures. RT_CHAOS_SEED replays one.
chaos: build samples
	$(PY) -m pytest -q -s tests/chaos/chaos_cluster.py

# The charts under docs/charts (PNG, CSV and Markdown each, an index.json the
# viewer's /charts page reads, and README.md): error against render time for each
# sampling method and what max_depth and the cutoff trade; the stability probes;
# scaling with triangles, threads and Dask workers. Times are wall clock on every
# core: run it with nothing else busy. References (many samples) are cached in
# build/charts, so a rerun only times the test points.
charts: build samples
	$(PY) renderer/bench/speed_accuracy.py --scenes $(SCENES) --out docs/charts --cache $(BUILD)/charts
	$(PY) renderer/bench/stability_charts.py --table $(BUILD)/renderer/stability_table --out docs/charts \
	  --cache $(BUILD)/charts/stability
	$(PY) renderer/bench/scaling.py --scenes $(SCENES) --rtrender $(BUILD)/rtrender --out docs/charts \
	  --work $(BUILD)/charts/scaling

clean:
	rm -rf $(BUILD)
