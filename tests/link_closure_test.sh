#!/usr/bin/env bash
# The dependency rules of docs/architecture.md that a build does not enforce by itself:
# - skilld runs its policies in Eigen and must not link libtorch; skillctl and skillweb are DDS
#   clients and must link neither libtorch, nor MuJoCo, nor OMPL. Checked on what CMake hands the
#   linker (the closure of the targets, whatever the linker then drops) and on what the binaries load.
# - No client file includes a server header: no #include of server/ in client/, and no file under
#   server/ among what the compiler read for the client targets' objects (their depfiles), so that
#   none comes in through another header either.
# - The hardware driver has no MuJoCo: no #include of sim/ or MuJoCo in hw/, nor among what the
#   compiler read for flsd_hw's objects; and flsd_hw's link closure (that of hw_a1_protocol_test,
#   which links flsd_hw alone) names no MuJoCo.
# - The controller knows no DDS: its objects (the controller, its stand sequence, task tracker and
#   request queue) were compiled from no Cyclone header and no IDL type; the calls and names it
#   uses are api/'s.
set -euo pipefail
build=${1:?usage: link_closure_test.sh BUILD_DIR SOURCE_DIR}
source=$(cd "${2:?usage: link_closure_test.sh BUILD_DIR SOURCE_DIR}" && pwd)  # as depfiles name it
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
includes() {  # source folder, forbidden include pattern (after the < or ")
  local hits
  hits=$(grep -rnE --include='*.h' --include='*.cc' "^[[:space:]]*#[[:space:]]*include[[:space:]]*[<\"]($2)" \
         "$source/$1" || true)
  if [ -n "$hits" ]; then
    echo "FAIL: $1/ includes $2:"
    echo "$hits"
    failures=$((failures + 1))
  fi
}
reads() {  # build folder, target, object pattern, forbidden paths (fixed strings)...: what the compiler read
  local folder=$1 target=$2 only=$3 objects patterns=() hits=""
  shift 3
  # The target's objects as its link command lists them (a removed source's stale object is not),
  # those whose names match `only`.
  objects=$(grep -oE "CMakeFiles/$target\.dir/[^ ]+\.o" "$build/$folder/CMakeFiles/$target.dir/link.txt" |
            grep -E "$only" || true)
  if [ -z "$objects" ]; then
    echo "FAIL: no objects of $target in its link command"
    failures=$((failures + 1))
  fi
  for path in "$@"; do patterns+=(-e "$path"); done
  for object in $objects; do
    if [ ! -f "$build/$folder/$object.d" ]; then
      echo "FAIL: no depfile for $folder/$object"
      failures=$((failures + 1))
    elif grep -qF "${patterns[@]}" "$build/$folder/$object.d"; then
      hits+="  $folder/$object"$'\n'
    fi
  done
  if [ -n "$hits" ]; then
    echo "FAIL: $target was compiled from $*:"
    echo -n "$hits"
    failures=$((failures + 1))
  fi
}
check "$build/bin/skilld" "$build/server/CMakeFiles/skilld.dir/link.txt" 'libtorch|libc10'
check "$build/bin/skillctl" "$build/client/CMakeFiles/skillctl.dir/link.txt" 'libtorch|libc10' 'libmujoco' 'libompl'
check "$build/bin/skillweb" "$build/client/web/CMakeFiles/skillweb.dir/link.txt" 'libtorch|libc10' 'libmujoco' 'libompl'
includes client 'server/'
for target in flsd_client skillctl; do reads client $target . "$source/server/"; done
for target in flsd_web skillweb; do reads client/web $target . "$source/server/"; done
includes hw 'sim/|mujoco'
reads hw flsd_hw . "$source/sim/" /mujoco/
reads server flsd_server '/(controller|stand_sequence|task_tracker|request_queue)\.cc\.o$' \
  /dds/ flsd_msgs.h "$source/comm/dds.h" "$source/comm/protocol.h" "$source/comm/security.h"
check "$build/tests/hw_a1_protocol_test" "$build/tests/CMakeFiles/hw_a1_protocol_test.dir/link.txt" 'libmujoco'
echo "link closure and includes: $failures violations"
[ "$failures" -eq 0 ]
