#!/usr/bin/env bash
# Installs the Debian 12 packages Motion LOD Studio builds and tests with (as root).
# Idempotent: when every package is already installed, apt is not touched at all.
set -euo pipefail

packages=(
  build-essential cmake ninja-build ccache dpkg-dev file pkg-config
  qt6-base-dev qt6-base-dev-tools qt6-tools-dev qt6-tools-dev-tools qt6-charts-dev qt6-svg-dev
  libqt6opengl6-dev
  libassimp-dev assimp-utils assimp-testmodels libopenmesh-dev libglm-dev libmeshoptimizer-dev
  libtinygltf-dev nlohmann-json3-dev libcli11-dev libgtest-dev libbenchmark-dev
  libgl-dev libgl1-mesa-dri xvfb xauth clang libclang-rt-14-dev
  appstream desktop-file-utils jq man-db valgrind
)

missing=()
for package in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${db:Status-Status}' "$package" 2>/dev/null || true)
  [ "$status" = "installed" ] || missing+=("$package")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages are installed"
  exit 0
fi

if [ "$(id -u)" -ne 0 ]; then
  echo "install-deps: missing ${missing[*]}; run as root (or: sudo bash $0)" >&2
  exit 1
fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}"
