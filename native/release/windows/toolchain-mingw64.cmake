# Cross-compiling for 64-bit Windows with Debian's MinGW-w64 (packages mingw-w64,
# g++-mingw-w64-x86-64-posix, libz-mingw-w64-dev). The posix-threads compilers provide std::thread
# and OpenMP. Everything is linked statically, so mwb-engine.exe and the test programs need no DLL
# beside them (only Windows' own).
set(CMAKE_SYSTEM_NAME Windows)
set(CMAKE_SYSTEM_PROCESSOR x86_64)
set(MWB_MINGW_TRIPLET x86_64-w64-mingw32)
set(CMAKE_C_COMPILER ${MWB_MINGW_TRIPLET}-gcc-posix)
set(CMAKE_CXX_COMPILER ${MWB_MINGW_TRIPLET}-g++-posix)
set(CMAKE_RC_COMPILER ${MWB_MINGW_TRIPLET}-windres)
set(CMAKE_FIND_ROOT_PATH /usr/${MWB_MINGW_TRIPLET})
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
set(CMAKE_EXE_LINKER_FLAGS_INIT -static)
# ODE's autotools configure (native/ode/BundledOde.cmake) builds for this host.
set(MWB_ODE_HOST ${MWB_MINGW_TRIPLET})
# In strict C++17 mode MinGW's <math.h> defines M_PI only when asked (glibc's always does for g++).
set(CMAKE_CXX_FLAGS_INIT -D_USE_MATH_DEFINES)
# The import libraries (.dll.a) come first in a search; the static archives are wanted.
execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libgomp.a
                OUTPUT_VARIABLE _mwb_libgomp OUTPUT_STRIP_TRAILING_WHITESPACE)
set(OpenMP_gomp_LIBRARY ${_mwb_libgomp} CACHE FILEPATH "OpenMP's static runtime")
set(ZLIB_LIBRARY /usr/${MWB_MINGW_TRIPLET}/lib/libz.a CACHE FILEPATH "static zlib")
