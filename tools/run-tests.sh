#!/usr/bin/env bash
# The whole test suite from a fresh clone: install what is missing, build everything, run CTest.
# The tests run the real kernels on PoCL (SDFBRICK_TEST_DEVICE=cpu by default) and fail when no
# OpenCL device is found.
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake --preset release >/dev/null
cmake --build build/release -j"$(nproc)"
ctest --test-dir build/release --output-on-failure -j"$(nproc)"
