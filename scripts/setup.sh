#!/usr/bin/env bash
# Installs what GeoFilter needs on Debian 12 (as root) and extracts the real meshes into
# meshes/. Only installs packages: no apt source is added, no system file is edited.
set -euo pipefail
top=$(cd "$(dirname "$0")/.." && pwd)

packages=(
    build-essential cmake                 # the build
    ccache                                # a compiler cache: the test command's second run rebuilds little
    meshlab                               # MeshLab 2020.09: meshlab, meshlabserver, libmeshlab-common.so
    dpkg-dev                              # apt-get source / dpkg-source, for MeshLab's headers and vcglib (the plugin only)
    file                                  # what CPack's Debian generator reads the libraries' dependencies with
    qtbase5-dev libqt5opengl5-dev libglew-dev   # what MeshLab's headers include
    libeigen3-dev libsuitesparse-dev      # the core: Eigen and CHOLMOD
    libmumps-seq-dev                      # exact solves of sharp complex pole pairs (sequential MUMPS)
    libopenblas0-pthread                  # a multithreaded BLAS under CHOLMOD (2x faster factorisation)
    libgtest-dev                          # unit tests
    clang libclang-rt-14-dev              # libFuzzer (scripts/fuzz.sh)
    xvfb xauth xfonts-base                # meshlabserver needs an X display (Xvfb its 'fixed' font)
    python3-numpy python3-matplotlib      # integration tests, plots and renders
    pybind11-dev python3-dev python3-pytest   # the Python module and its tests
    gnuplot-nox                           # G(s) and benchmark plots
    libcgal-demo                          # real meshes (data.tar.gz)
    libopenmpi-dev openmpi-bin petsc-dev libmumps-dev   # geofilter-mpi: MPI, PETSc 3.18 (MUMPS, hypre, PT-Scotch)
)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
    echo "setup: installing ${missing[*]}"
    if [ "$(id -u)" -ne 0 ]; then
        echo "setup: these packages are missing and installing them needs root: ${missing[*]}" >&2
        exit 1
    fi
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -q
    # What is listed and what it depends on, not what it recommends (about 520 packages
    # on a minimal Debian 12 instead of 710: no LLVM, ImageMagick, GTK or systemd).
    apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

"$top/scripts/fetch-meshes.sh"
