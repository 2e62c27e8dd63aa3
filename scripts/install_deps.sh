#!/usr/bin/env bash
# Installs the Debian packages FLSD needs. Idempotent: exits quickly when all are present.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libmujoco-dev libosmesa6-dev libpng-dev libgif-dev
  libeigen3-dev liburdfdom-dev
  libyaml-cpp-dev libcli11-dev libspdlog-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libtorch-dev libopenblas0-pthread
  cyclonedds-dev cyclonedds-tools openssl libssl-dev
  libcpp-httplib-dev
  libfastrtps-dev fastddsgen
  libompl-dev
  libopenmpi-dev openmpi-bin
  chromium
  pybind11-dev python3-dev python3-pytest
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
# skillweb's page is bundled with npm. A NodeSource Node.js brings its own npm and conflicts with
# Debian's npm package, so Debian's Node.js and npm come only where there is no npm at all.
command -v npm > /dev/null || missing+=(nodejs npm)
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install_deps: installing ${missing[*]}"
sudo_cmd=()
[ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
