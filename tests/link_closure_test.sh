#!/usr/bin/env bash
# The serving binaries' link closure: skilld runs its policies in Eigen and must not link libtorch;
# skillctl and skillweb are DDS clients and must link neither libtorch, nor MuJoCo, nor OMPL. Checked on what
# CMake hands the linker (the closure of the targets, whatever the linker then drops) and on what
# the binaries load.
set -euo pipefail
build=${1:?usage: link_closure_test.sh BUILD_DIR}
failures=0
check() {  # binary, link command file, forbidden library patterns...
  local binary=$1 link=$2
  shift 2
  for library in "$@"; do
    if grep -Eq "$library" "$link"; then
      echo "FAIL: $(basename "$binary") is linked against $library ($link)"
      failures=$((failures + 1))
    fi
    if readelf -d "$binary" | grep NEEDED | grep -Eq "$library"; then
      echo "FAIL: $(basename "$binary") loads $library"
      failures=$((failures + 1))
    fi
  done
}
check "$build/bin/skilld" "$build/server/CMakeFiles/skilld.dir/link.txt" 'libtorch|libc10'
check "$build/bin/skillctl" "$build/client/CMakeFiles/skillctl.dir/link.txt" 'libtorch|libc10' 'libmujoco' 'libompl'
check "$build/bin/skillweb" "$build/client/web/CMakeFiles/skillweb.dir/link.txt" 'libtorch|libc10' 'libmujoco' 'libompl'
echo "link closure: $failures violations"
[ "$failures" -eq 0 ]
