#!/usr/bin/env bash
# make demo: skilld with the simulated A1 and the shipped skill library, driven by skillctl the way
# a user would: list the skills, stand, run the four fastest ones (each from rest), track a
# velocity with the skill selector, navigate around the obstacles of configs/maps/demo.yaml
# (writing a picture of the planned and the walked path to $PICTURE), then stop the server cleanly.
# Everything stays on this machine (Cyclone on loopback, a partition of its own).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${BIN_DIR:-build/bin}
library=${LIBRARY:-models/a1_flsd.safetensors}
export CYCLONEDDS_URI=${CYCLONEDDS_URI:-file://$PWD/configs/cyclonedds_loopback.xml}
domain=${DOMAIN:-42}
partition="demo-$$"
ctl=("$bin/skillctl" --domain "$domain" --partition "$partition" --timeout 10)

[ -f "$library" ] || { echo "demo: no skill library at $library (export one with: flsd export RUN -o $library)"; exit 2; }

"$bin/skilld" --backend sim --library "$library" --domain "$domain" --partition "$partition" &
server=$!
trap 'kill -INT $server 2>/dev/null; wait $server' EXIT

echo "== skills in $library"
"${ctl[@]}" list | tee /tmp/flsd_demo_skills.$$
echo "== stand"
"${ctl[@]}" stand
# The four skills with the largest mean speed (m/s, plus 0.3 m per radian of turning).
fastest=$(awk 'NR > 1 { printf "%s %f\n", $1, sqrt($2*$2 + $3*$3) + 0.3*($4 < 0 ? -$4 : $4) }' /tmp/flsd_demo_skills.$$ |
          sort -k2 -g -r | head -4 | cut -d' ' -f1)
rm -f /tmp/flsd_demo_skills.$$
status=0
for k in $fastest; do
  # Each skill from a standing start at rest, as the library's evaluation ran it. The simulated
  # robot is reset first: a skill that turns fast can leave the robot tipping as the stand takes
  # over (docs/selector.md), and no skill was trained to take over mid-stride.
  "${ctl[@]}" reset >/dev/null
  "${ctl[@]}" stand >/dev/null
  echo "== skill $k for 4 s"
  "${ctl[@]}" --quiet skill "$k" --duration 4 || status=$?
done
"${ctl[@]}" reset >/dev/null
"${ctl[@]}" stand >/dev/null
echo "== track 0.4 m/s forward for 4 s (the selector chooses the skills)"
"${ctl[@]}" --quiet vel 0.4 0 0 --duration 4 || status=$?
"${ctl[@]}" stand >/dev/null
picture=${PICTURE:-build/demo_navigation.svg}
echo "== reset: back to the origin of the map"
"${ctl[@]}" reset >/dev/null
echo "== navigate to (5, 0) around the obstacles of configs/maps/demo.yaml"
"${ctl[@]}" --quiet goto 5 0 --map configs/maps/demo.yaml --duration 60 --picture "$picture" || status=$?
echo "== status"
"${ctl[@]}" status
exit $status
