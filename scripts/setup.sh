#!/usr/bin/env bash
# Installs the Debian packages sluice builds and tests with. Idempotent: only what is missing is
# installed. Run as root (or with sudo available) on Debian 12.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libcli11-dev libtomlplusplus-dev libfmt-dev zlib1g-dev libhwy-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libpng-dev libgif-dev libfreetype-dev fonts-dejavu-core
  libassimp-dev libcgal-dev
  python3 python3-numpy python3-meshio python3-pil
  # Several processes: MPI (Open MPI, with mpirun) and Zoltan's domain decomposition.
  libopenmpi-dev openmpi-bin libtrilinos-zoltan-dev
  # sluice view: an HTTP server and JSON for its page.
  libcpp-httplib-dev nlohmann-json3-dev
  # The view's page tested in a headless browser.
  chromium
  # The Python module (`import sluice`) and its tests: pybind11, the interpreter's headers, pytest, and
  # Jupyter's notebook runner with its Python kernel, and mpi4py for the module under mpirun; the
  # examples plot with matplotlib.
  pybind11-dev python3-dev python3-pytest python3-nbclient python3-nbformat python3-ipykernel python3-matplotlib
  python3-mpi4py
  # The documentation site (`make docs`): Sphinx with MyST Markdown.
  python3-sphinx python3-myst-parser
)
# `make fuzz` (scripts/setup.sh fuzz) also needs clang with its libFuzzer and sanitizer runtimes, and
# LLVM's OpenMP for the solver library built with clang.
if [ "${1:-}" = fuzz ]; then
  packages+=(clang libclang-rt-14-dev libomp-14-dev)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo="sudo"
fi
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -q >/dev/null || { echo "setup: apt-get update failed" >&2; exit 1; }
$sudo apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
