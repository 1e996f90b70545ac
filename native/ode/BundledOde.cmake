# ODE for the engine and the module, as the target mwb_ode.
#
# By default ODE 0.16.2 and libccd 2.1 are built here from Debian's source packages, configured as
# Debian configures them (double precision; libccd for the convex and cylinder pairs; OPCODE for
# trimeshes), so worlds come out bit for bit as with Debian's libode8. Both are static and
# position-independent, so the engine and the Python module need nothing outside glibc at run
# time. native/ode/per-thread-random.patch keeps the generator quickstep draws from per thread, so
# each world steps with its own state. MWB_SYSTEM_ODE=ON links the system's libode instead (for
# packagers); the engine then replaces ODE's generator through the symbol table.
option(MWB_SYSTEM_ODE "Link the system's libode (pkg-config ode) instead of building ODE from source" OFF)

if(MWB_SYSTEM_ODE)
  pkg_check_modules(ODE REQUIRED IMPORTED_TARGET ode)
  add_library(mwb_ode INTERFACE)
  target_link_libraries(mwb_ode INTERFACE PkgConfig::ODE)
  set(MWB_ODE_BUILD "system libode ${ODE_VERSION}")
  return()
endif()

set(MWB_ODE_SOURCE_DIR ${CMAKE_BINARY_DIR}/ode-source CACHE PATH
    "folder with ode_0.16.2.orig.tar.gz and libccd_2.1.orig.tar.gz; fetched from Debian when missing")
if(NOT EXISTS ${MWB_ODE_SOURCE_DIR}/ode_0.16.2.orig.tar.gz OR
   NOT EXISTS ${MWB_ODE_SOURCE_DIR}/libccd_2.1.orig.tar.gz)
  message(STATUS "Fetching ODE 0.16.2 and libccd 2.1 from Debian's source packages")
  execute_process(COMMAND sh ${CMAKE_CURRENT_LIST_DIR}/fetch_ode_source.sh ${MWB_ODE_SOURCE_DIR}
                  RESULT_VARIABLE _ode_fetch_result)
  if(NOT _ode_fetch_result EQUAL 0)
    message(FATAL_ERROR "ODE's source could not be fetched into ${MWB_ODE_SOURCE_DIR}; "
                        "MWB_SYSTEM_ODE=ON builds against the system's libode instead")
  endif()
endif()

# -ffp-contract=off: no fused multiply-adds even where a target has them, so the arithmetic is the
# same whatever the compiler or machine.
set(_ode_flags "-O2 -ffp-contract=off")
set(MWB_ODE_INSTALL_DIR ${CMAKE_BINARY_DIR}/ode-install)
set(_ode_lib ${MWB_ODE_INSTALL_DIR}/lib/libode.a)
set(_ccd_lib ${MWB_ODE_INSTALL_DIR}/lib/libccd.a)
set(_ode_host "")
if(CMAKE_CROSSCOMPILING AND MWB_ODE_HOST)
  set(_ode_host --host=${MWB_ODE_HOST})
endif()
set(_ode_patch patch -p1 -i ${CMAKE_CURRENT_LIST_DIR}/per-thread-random.patch)
if(CMAKE_CROSSCOMPILING AND WIN32)
  # MinGW-w64's headers are lower-case, which matters on the Linux machine that cross-compiles.
  list(APPEND _ode_patch COMMAND patch -p1 -i ${CMAKE_CURRENT_LIST_DIR}/mingw-windows-header.patch)
endif()
set(_ode_toolchain -DCMAKE_C_COMPILER=${CMAKE_C_COMPILER})
if(CMAKE_TOOLCHAIN_FILE)
  list(APPEND _ode_toolchain -DCMAKE_TOOLCHAIN_FILE=${CMAKE_TOOLCHAIN_FILE})
endif()
# CMake 4 refuses projects that ask for a version below 3.5, as libccd 2.1 does; it builds the same
# with the 3.5 policies (ODE itself uses autotools).
set(_ccd_policy "")
if(CMAKE_VERSION VERSION_GREATER_EQUAL 4.0)
  set(_ccd_policy -DCMAKE_POLICY_VERSION_MINIMUM=3.5)
endif()
include(ExternalProject)
if(POLICY CMP0135)
  # Extracted files keep the archive's times: ODE's generated configure and Makefile.in must stay
  # newer than configure.ac, or make would ask for automake.
  cmake_policy(SET CMP0135 OLD)
endif()

ExternalProject_Add(ccd_from_source
  URL ${MWB_ODE_SOURCE_DIR}/libccd_2.1.orig.tar.gz
  URL_HASH SHA256=3543093486a8bdb7129e18d69d8f2b42e3056877521425210f9fe560789ebba5
  CMAKE_ARGS
    ${_ode_toolchain}
    ${_ccd_policy}
    -DCMAKE_BUILD_TYPE=Release
    -DCMAKE_C_FLAGS=${_ode_flags}
    -DCMAKE_INSTALL_PREFIX=${MWB_ODE_INSTALL_DIR}
    -DCMAKE_INSTALL_LIBDIR=lib
    -DCMAKE_POSITION_INDEPENDENT_CODE=ON
    -DBUILD_SHARED_LIBS=OFF
    -DBUILD_TESTING=OFF
    -DCCD_DOUBLE=ON
    -Wno-dev
  BUILD_BYPRODUCTS ${_ccd_lib}
  LOG_CONFIGURE ON
  LOG_BUILD ON
  LOG_INSTALL ON
)

# ODE's own autotools build, in its source folder as Debian builds it: an out-of-tree build would
# pick up the single-precision precision.h that the source archive ships.
ExternalProject_Add(ode_from_source
  DEPENDS ccd_from_source
  URL ${MWB_ODE_SOURCE_DIR}/ode_0.16.2.orig.tar.gz
  URL_HASH SHA256=b26aebdcb015e2d89720ef48e0cb2e8a3ca77915f89d853893e7cc861f810f22
  PATCH_COMMAND ${_ode_patch}
  BUILD_IN_SOURCE ON
  CONFIGURE_COMMAND ${CMAKE_COMMAND} -E env
    PKG_CONFIG_PATH=${MWB_ODE_INSTALL_DIR}/lib/pkgconfig
    CC=${CMAKE_C_COMPILER} CXX=${CMAKE_CXX_COMPILER}
    CFLAGS=${_ode_flags} CXXFLAGS=${_ode_flags}
    <SOURCE_DIR>/configure ${_ode_host} --prefix=${MWB_ODE_INSTALL_DIR} --libdir=${MWB_ODE_INSTALL_DIR}/lib
    --enable-double-precision --enable-libccd --with-libccd=system
    --disable-shared --enable-static --with-pic --disable-demos
  BUILD_COMMAND $(MAKE)
  INSTALL_COMMAND $(MAKE) install
  # ODE's and libccd's calls of the C library's sin, cos, atan2, ... go to our portable
  # functions (common/PortableMath), whose results do not change with the glibc version.
  COMMAND ${CMAKE_OBJCOPY} --redefine-syms=${CMAKE_CURRENT_LIST_DIR}/portable-math.syms ${_ode_lib}
  COMMAND ${CMAKE_OBJCOPY} --redefine-syms=${CMAKE_CURRENT_LIST_DIR}/portable-math.syms ${_ccd_lib}
  BUILD_BYPRODUCTS ${_ode_lib}
  LOG_CONFIGURE ON
  LOG_BUILD ON
  LOG_INSTALL ON
)

# The include folder must exist when the imported targets are defined.
file(MAKE_DIRECTORY ${MWB_ODE_INSTALL_DIR}/include)
find_package(Threads REQUIRED)
add_library(mwb_ccd STATIC IMPORTED GLOBAL)
set_target_properties(mwb_ccd PROPERTIES IMPORTED_LOCATION ${_ccd_lib})
add_dependencies(mwb_ccd ccd_from_source)
add_library(mwb_ode STATIC IMPORTED GLOBAL)
set_target_properties(mwb_ode PROPERTIES
  IMPORTED_LOCATION ${_ode_lib}
  INTERFACE_INCLUDE_DIRECTORIES ${MWB_ODE_INSTALL_DIR}/include
  INTERFACE_COMPILE_DEFINITIONS "dIDEDOUBLE;MWB_ODE_PER_THREAD_RANDOM"
  INTERFACE_LINK_LIBRARIES "mwb_ccd;mwb_common;Threads::Threads")
add_dependencies(mwb_ode ode_from_source)
set(MWB_ODE_BUILD "ODE 0.16.2 + libccd 2.1 (Debian source), per-thread random, portable math, ${_ode_flags}")
# A changed symbol list renames again.
ExternalProject_Add_StepDependencies(ode_from_source install ${CMAKE_CURRENT_LIST_DIR}/portable-math.syms)
