# Thin wrapper around CMake so the README's commands stay short.
#   make demo   build, then render scenes/demo.yml into out/demo
#   make test   build, then run every test (ctest)
#   make install  install the build (PREFIX, default /usr/local; DESTDIR honoured)
BUILD ?= build
JOBS  ?= $(shell nproc 2>/dev/null || echo 2)

.PHONY: all deps build demo test install clean
all: build

deps:
	@tools/install-deps.sh

build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release
	cmake --build $(BUILD) -j $(JOBS)

demo: build
	./$(BUILD)/curray -s scenes/demo.yml -o out/demo -x 640 -y 480 -a true
	@echo "demo image: out/demo/c_0.png"

test: build
	cd $(BUILD) && ctest --output-on-failure --no-tests=error -j $(JOBS)

install: build
	cmake --install $(BUILD) $(if $(PREFIX),--prefix $(PREFIX))

clean:
	rm -rf $(BUILD)
