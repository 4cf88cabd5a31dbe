#!/usr/bin/env bash
# Installs the Debian packages shellfrac needs to build, test, benchmark and preview.
# Installs only what is missing; runs non-interactively; safe to run repeatedly.
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  libeigen3-dev          # linear algebra (nurbs, shell, mpm)
  nlohmann-json3-dev     # scene files, summary.json
  libcli11-dev           # command-line parsing
  libtbb-dev             # threads
  libassimp-dev          # mesh import and export (OBJ and every assimp format)
  libopenvdb-dev libboost-iostreams-dev  # level sets of imported meshes (solids, mesh colliders)
  libgtest-dev libgmock-dev  # tests
  libbenchmark-dev       # micro-benchmarks
  libboost-dev           # Boost.Polygon Voronoi diagrams (crack2d)
  libceres-dev           # independent least-squares cross-check of the MLS fit (tests)
  gnuplot-nox            # benchmark charts
  blender                # `shellfrac preview` and the Blender import tests (Cycles on the CPU)
  python3                # drivers of the Blender tests (tests/blender/, standard library only)
  voro++-dev             # 3D Voronoi diagrams of damaged regions (brittle crack surfaces)
  libcgal-dev libgmp-dev libmpfr-dev  # exact mesh booleans for fragments (brittle)
  libbullet-dev          # rigid bodies of the shatter loop (rigid/)
  libmeshoptimizer-dev   # decimated collision meshes of breakable bodies (rigid/)
  libsuitesparse-dev     # CHOLMOD, the sparse Cholesky of the phase-field solve (brittle/)
  pybind11-dev python3-dev  # the Python module (python/, docs/python.md)
  python3-numpy python3-pytest python3-matplotlib  # its arrays, its tests (tests/python/), its examples
  python3-distributed    # sweeps on a Dask cluster (python/shellfrac/sweep.py, `shellfrac bench verify --dask`)
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages already installed"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  if command -v sudo >/dev/null 2>&1; then SUDO="sudo"; else
    echo "setup: need root (or sudo) to install: ${missing[*]}" >&2; exit 1
  fi
fi

echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
