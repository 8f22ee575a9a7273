#!/bin/sh
# Builds and runs bench/amg_libraries.cpp inside the project's Debian 13 root:
#   ./yadew sh sh bench/amg_libraries.sh [LARGEST_BODIES [cubic|random]]   (default: up to ~10⁵ bodies, both beds)
# hypre (libhypre-dev) and PETSc (libpetsc-real-dev, with OpenMPI) are installed here for this
# measurement only; the product links neither.  The program initialises MPI itself (a singleton
# process, no mpirun).  VISCBRIDGE_SKIP_BUILD=1 before ./yadew skips rebuilding the plugin.
set -e
cd "$(dirname "$0")/.."
for p in libsuitesparse-dev libhypre-dev libpetsc-real-dev; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'ok installed' \
    || apt-get install -y -q --no-install-recommends "$p" >/dev/null
done
out=/tmp/viscbridge-amg-libraries
# the plugin's flags for our code (Release, Eigen unvectorised as YADE builds it); PETSc and MPI
# through pkg-config, hypre from /usr/include/hypre
g++ -std=c++17 -O3 -DNDEBUG -DEIGEN_DONT_VECTORIZE -Ipkg -I/usr/include/eigen3 -I/usr/include/suitesparse -I/usr/include/hypre \
    $(pkg-config --cflags petsc mpi) -o "$out" bench/amg_libraries.cpp \
    $(pkg-config --libs petsc mpi) -lHYPRE -lcholmod -lsuitesparseconfig
# hwloc finds no /sys in the root and would say so once per run
HWLOC_COMPONENTS=-linux OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1 "$out" "$@"
