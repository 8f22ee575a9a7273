#!/bin/sh
# Builds and runs bench/factor_libraries.cpp inside the project's Debian 13 root:
#   ./yadew sh sh bench/factor_libraries.sh [LARGEST_SIDE]      (default 22: up to ~10⁴ bodies)
# SuiteSparse (CHOLMOD) is installed here for this measurement only; the product does not link it.
set -e
cd "$(dirname "$0")/.."
dpkg-query -W -f='${Status}' libsuitesparse-dev 2>/dev/null | grep -q 'ok installed' \
  || apt-get install -y -q --no-install-recommends libsuitesparse-dev >/dev/null
out=/tmp/viscbridge-factor-libraries
# the plugin's flags (Release, Eigen unvectorised as YADE builds it)
g++ -std=c++17 -O3 -DNDEBUG -DEIGEN_DONT_VECTORIZE -fopenmp -Ipkg -I/usr/include/eigen3 -I/usr/include/suitesparse \
    -o "$out" bench/factor_libraries.cpp -lcholmod -lsuitesparseconfig
OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 "$out" "$@"
