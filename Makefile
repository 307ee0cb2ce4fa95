# The two commands a user needs: `make run` and `make test`.
BUILD_DIR ?= build
BUILD_TYPE ?= Release
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps configure build run test sanitize tsan fuzz clean

all: build

deps:
	bash scripts/install-deps.sh

configure: deps
	cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=$(BUILD_TYPE) $(CMAKE_FLAGS)

build: configure
	cmake --build $(BUILD_DIR) -j $(JOBS)

# Starts tesserad on loopback, renders examples/scenes/cornell.yaml through it,
# writes out/cornell.exr and out/cornell.png, then stops the daemon.
run: build
	bash scripts/run-demo.sh $(BUILD_DIR)

test: build
	cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS) --timeout 600

# Every unit and integration test under AddressSanitizer + UndefinedBehaviorSanitizer
# (build-asan/), and the server's and the CLI's tests under ThreadSanitizer (build-tsan/).
# Not part of `make test`: they take several times as long (see README, "Sanitizers").
SANITIZER_FLAGS = -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTESSERA_CUDA=OFF -DTESSERA_BUILD_BENCH=OFF
# Reports go to files in build-asan/sanitizer-reports/ as well as failing their test: a
# tesserad the test kills with SIGKILL, or whose log is removed when the test passes,
# would otherwise take its report with it. Any report file fails the target.
SANITIZER_REPORTS = $(CURDIR)/build-asan/sanitizer-reports
sanitize: deps
	cmake -S . -B build-asan $(SANITIZER_FLAGS) -DTESSERA_SANITIZE=ON
	cmake --build build-asan -j $(JOBS)
	rm -rf $(SANITIZER_REPORTS) && mkdir -p $(SANITIZER_REPORTS)
	cd build-asan && ASAN_OPTIONS=detect_leaks=1:log_path=$(SANITIZER_REPORTS)/asan \
	  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1:log_path=$(SANITIZER_REPORTS)/ubsan \
	  ctest --output-on-failure -j $(JOBS) -L "unit|integration" --timeout 1200; status=$$?; \
	  if [ -n "$$(ls -A $(SANITIZER_REPORTS))" ]; then cat $(SANITIZER_REPORTS)/*; exit 1; fi; \
	  exit $$status

# The suites with threads or a daemon in them (names are prefixes): the in-process and
# separate-process daemon tests, the scheduler, jobs, their store and WatchJobs, tile
# retries, the client and the CLI against a daemon, TLS and tokens, /metrics, the client's
# retries against a scripted server, and the CLI's multi-threaded local render. Left out:
# the resubmission of a 3-million-triangle scene, whose conversion and validation (twice)
# take 19 min under ThreadSanitizer, at the edge of the 20-min timeout and longer than all
# the rest together; DaemonTest.ConcurrentAttemptsOfOneRequestIdMakeOneJob runs the same
# race (attempts of one request id stored at once) on a small scene.
TSAN_TESTS = ^(Daemon|Scheduler|Job|TileRetryTest|TileFailureCount|SqliteJobStore|ClientServer|CliAgainstDaemon|CliScriptingTest|ClientRetryTest|SecurityTest|MetricsEndpoint|LocalRender)
TSAN_EXCLUDED = ^DaemonBudgetTest\.AResubmissionWithTheSameRequestIdAfterATimeoutCreatesOneJob$$
tsan: deps
	cmake -S . -B build-tsan $(SANITIZER_FLAGS) -DTESSERA_TSAN=ON
	cmake --build build-tsan -j $(JOBS) --target unit_server unit_client integration_tests tesserad tessera
	cd build-tsan && TSAN_OPTIONS="halt_on_error=1 suppressions=$(CURDIR)/tests/tsan.supp" \
	  ctest --output-on-failure -j $(JOBS) -R "$(TSAN_TESTS)" -E "$(TSAN_EXCLUDED)" --timeout 1200

# libFuzzer on the YAML loader and on SubmitJobRequest bytes (tests/fuzz), built with clang
# under ASan + UBSan in build-fuzz/, each run for FUZZ_SECONDS on a copy of its seed corpus
# (build-fuzz/corpus-*; findings in build-fuzz/findings-*). `make test` replays the seeds
# and fixed mutations of them without clang (FuzzReplay.*).
FUZZ_SECONDS ?= 60
FUZZ_FLAGS = -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTESSERA_CUDA=OFF -DTESSERA_BUILD_BENCH=OFF \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DTESSERA_SANITIZE=ON -DTESSERA_FUZZ=ON \
  -DCMAKE_CXX_FLAGS=-fsanitize=fuzzer-no-link -DCMAKE_C_FLAGS=-fsanitize=fuzzer-no-link
fuzz: deps
	cmake -S . -B build-fuzz $(FUZZ_FLAGS)
	cmake --build build-fuzz -j $(JOBS) --target fuzz_yaml_scene fuzz_proto_scene fuzz_proto_seeds
	bash tests/fuzz/run.sh build-fuzz $(FUZZ_SECONDS)

clean:
	rm -rf $(BUILD_DIR)
