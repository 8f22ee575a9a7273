# Locate the installed YADE and its same-version source tree; define the imported target
# yade::yade that carries YADE's headers, feature macros and libraries.
#
# Inputs : YADE_LIBDIR (installed library directory), YADE_SOURCE_DIR (upstream source tree).
# Outputs: YADE_VERSION, YADE_FEATURES, YADE_DEFINITIONS, YADE_LIBDIR_RELATIVE, target yade::yade,
#          function yade_make_overlay(PREFIX PLUGIN_FILE).

set(_yade_config "${YADE_LIBDIR}/py/yade/config.py")
if(NOT EXISTS "${_yade_config}")
  message(FATAL_ERROR "No installed YADE at YADE_LIBDIR=${YADE_LIBDIR} (missing ${_yade_config}).")
endif()

# yade.config is plain Python that only needs HOME; run it without importing the yade package
# (which would boot the whole C++ core).
execute_process(
  COMMAND ${Python3_EXECUTABLE} -c
    "import runpy,sys,os; c=runpy.run_path(sys.argv[1]); print(c['version']); print(','.join(f for f in c['features'] if f)); print(c['highPrecisionBits']); print(os.path.relpath(c['libDir'], c['prefix'])); print(c['prefix']); print(c['suffix'])"
    "${_yade_config}"
  OUTPUT_VARIABLE _yade_info OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _rc)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "Could not read ${_yade_config}")
endif()
string(REPLACE "\n" ";" _yade_info "${_yade_info}")
list(GET _yade_info 0 YADE_VERSION)
list(GET _yade_info 1 _features)
list(GET _yade_info 2 YADE_REAL_BITS)
list(GET _yade_info 3 YADE_LIBDIR_RELATIVE)  # e.g. lib/x86_64-linux-gnu/yade-double, below the prefix
list(GET _yade_info 4 YADE_PREFIX)            # /usr for Debian's package
list(GET _yade_info 5 YADE_SUFFIX)            # -double
string(REPLACE "," ";" YADE_FEATURES "${_features}")
if(NOT YADE_REAL_BITS EQUAL 64)
  message(FATAL_ERROR "ViscBridge supports the double-precision YADE (yade-double), found ${YADE_REAL_BITS}-bit Real.")
endif()

# The headers must come from exactly this release: a different one builds fine and then fails to
# load, or worse, loads with a different class layout.
if(NOT YADE_SOURCE_DIR OR NOT EXISTS "${YADE_SOURCE_DIR}/RELEASE")
  message(FATAL_ERROR "YADE_SOURCE_DIR='${YADE_SOURCE_DIR}' is not a YADE source tree (no RELEASE file). "
                      "./yadew provides the ${YADE_VERSION} source.")
endif()
file(READ "${YADE_SOURCE_DIR}/RELEASE" YADE_SOURCE_VERSION)
string(STRIP "${YADE_SOURCE_VERSION}" YADE_SOURCE_VERSION)
if(NOT YADE_SOURCE_VERSION STREQUAL YADE_VERSION)
  message(FATAL_ERROR "YADE version mismatch: installed YADE is ${YADE_VERSION}, headers in "
                      "${YADE_SOURCE_DIR} are ${YADE_SOURCE_VERSION}. Refusing to build.")
endif()

execute_process(
  COMMAND ${Python3_EXECUTABLE} ${CMAKE_CURRENT_LIST_DIR}/yade_feature_macros.py
          "${YADE_SOURCE_DIR}/CMakeLists.txt" "${_yade_config}"
  OUTPUT_VARIABLE YADE_DEFINITIONS OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _rc ERROR_VARIABLE _err)
if(NOT _rc EQUAL 0)
  message(FATAL_ERROR "Could not derive YADE's feature macros: ${_err}")
endif()
string(REPLACE "\n" ";" YADE_DEFINITIONS "${YADE_DEFINITIONS}")
message(STATUS "YADE ${YADE_VERSION}, features: ${YADE_FEATURES}")
message(STATUS "YADE feature macros: ${YADE_DEFINITIONS}")

add_library(yade::yade INTERFACE IMPORTED)
target_include_directories(yade::yade SYSTEM INTERFACE "${YADE_SOURCE_DIR}" ${Python3_INCLUDE_DIRS})
target_compile_definitions(yade::yade INTERFACE ${YADE_DEFINITIONS})
target_link_libraries(yade::yade INTERFACE
  "${YADE_LIBDIR}/libyade.so" "${YADE_LIBDIR}/libpkg_common.so" "${YADE_LIBDIR}/libpkg_dem.so")

# Libraries and include paths some features pull into YADE's headers.
find_package(Eigen3 REQUIRED NO_MODULE)
string(REPLACE "." "" _pyver "${Python3_VERSION_MAJOR}${Python3_VERSION_MINOR}")
find_package(Boost REQUIRED COMPONENTS python${_pyver} serialization log iostreams system)
target_link_libraries(yade::yade INTERFACE Eigen3::Eigen Boost::boost Boost::python${_pyver}
  Boost::serialization Boost::log Boost::iostreams Boost::system)
if("OPENMP" IN_LIST YADE_FEATURES)
  find_package(OpenMP REQUIRED COMPONENTS CXX)
  target_link_libraries(yade::yade INTERFACE OpenMP::OpenMP_CXX)
endif()
if("MPI" IN_LIST YADE_FEATURES)
  find_package(MPI REQUIRED COMPONENTS CXX)
  target_link_libraries(yade::yade INTERFACE MPI::MPI_CXX)
  # core/Subdomain.hpp (yade.mpy's subdomain, read by pkg/viscbridge/distributed/) includes
  # mpi4py's C API header
  execute_process(COMMAND ${Python3_EXECUTABLE} -c "import mpi4py; print(mpi4py.get_include())"
    OUTPUT_VARIABLE MPI4PY_INCLUDE_DIR OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE _rc)
  if(NOT _rc EQUAL 0)
    message(FATAL_ERROR "YADE has the MPI feature but mpi4py is not importable (install python3-mpi4py).")
  endif()
  # Searched before Python's include directory: there, mpi4py/ is a symlink, and the relative
  # "../../MPI.h" that mpi4py.h includes would be recorded as /usr/include/MPI.h, a dependency that
  # never exists, so that make rebuilt the plugin on every ./yadew run.
  target_include_directories(yade::yade SYSTEM BEFORE INTERFACE "${MPI4PY_INCLUDE_DIR}")
endif()
if("GTS" IN_LIST YADE_FEATURES)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(GLIB2 REQUIRED IMPORTED_TARGET glib-2.0)
  target_link_libraries(yade::yade INTERFACE PkgConfig::GLIB2)
endif()

# Mirror the installed library directory into PREFIX/<libPATH>/yade<suffix>, plus a link to each
# PLUGIN_FILE (which need not exist yet).  yade-batch starts its jobs with PREFIX/bin/yade<suffix>,
# so that is linked too.
function(yade_make_overlay prefix)
  set(dir "${prefix}/${YADE_LIBDIR_RELATIVE}")
  file(REMOVE_RECURSE "${prefix}")
  file(MAKE_DIRECTORY "${dir}")
  file(GLOB entries RELATIVE "${YADE_LIBDIR}" "${YADE_LIBDIR}/*")
  foreach(e IN LISTS entries)
    file(CREATE_LINK "${YADE_LIBDIR}/${e}" "${dir}/${e}" SYMBOLIC)
  endforeach()
  foreach(plugin_file IN LISTS ARGN)
    get_filename_component(name "${plugin_file}" NAME)
    file(CREATE_LINK "${plugin_file}" "${dir}/${name}" SYMBOLIC)
  endforeach()
  file(MAKE_DIRECTORY "${prefix}/bin")
  file(CREATE_LINK "${YADE_PREFIX}/bin/yade${YADE_SUFFIX}" "${prefix}/bin/yade${YADE_SUFFIX}" SYMBOLIC)
  set(YADE_OVERLAY_PREFIX "${prefix}" PARENT_SCOPE)
endfunction()
