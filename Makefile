# Two commands do everything on a fresh Debian 12 machine: `make demo` and `make test`.
BUILD_DIR ?= build
JOBS ?= $(shell nproc)

.PHONY: deps configure build test demo serve bench clean

deps:
	@bash scripts/install_deps.sh

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release > $(BUILD_DIR).configure.log 2>&1 || \
	  (cat $(BUILD_DIR).configure.log; exit 1)

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

demo: build
	@BIN_DIR=$(BUILD_DIR)/bin bash scripts/demo.sh

# skilld with the simulated A1 and the shipped skills on loopback (domain 0, partition flsd: the
# defaults of skillctl, skillweb and the examples) until Ctrl-C.
serve: build
	@CYCLONEDDS_URI=$${CYCLONEDDS_URI:-file://$(CURDIR)/configs/cyclonedds_loopback.xml} \
	  $(BUILD_DIR)/bin/skilld --backend sim --library models/a1_flsd.safetensors

bench: build
	@$(BUILD_DIR)/bin/flsd bench sim --json

clean:
	@rm -rf $(BUILD_DIR) $(BUILD_DIR).configure.log
