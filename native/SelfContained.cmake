# mwb_openmp: OpenMP for the core. With MWB_SELF_CONTAINED, the engine and the module carry their
# C++ runtime and zlib inside them, so on another Linux they need only glibc (and the module its
# libgomp, below); no symbol of those libraries is exported from the module, so they cannot clash
# with the copies Blender or other add-ons load.
add_library(mwb_openmp INTERFACE)
if(NOT MWB_SELF_CONTAINED)
  target_link_libraries(mwb_openmp INTERFACE OpenMP::OpenMP_CXX)
  return()
endif()

execute_process(COMMAND ${CMAKE_CXX_COMPILER} -print-file-name=libgomp.a
                OUTPUT_VARIABLE MWB_LIBGOMP_STATIC OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT IS_ABSOLUTE "${MWB_LIBGOMP_STATIC}" OR NOT EXISTS "${MWB_LIBGOMP_STATIC}")
  message(FATAL_ERROR "MWB_SELF_CONTAINED needs OpenMP's static runtime (libgomp.a), which "
                      "${CMAKE_CXX_COMPILER} does not have")
endif()
find_package(Threads REQUIRED)
# Executables link libgomp.a. Its thread-local data uses a TLS model only an executable can hold,
# so a shared module links libgomp.so.1 instead, which ships beside it (found through $ORIGIN).
set(_is_executable "$<STREQUAL:$<TARGET_PROPERTY:TYPE>,EXECUTABLE>")
target_compile_options(mwb_openmp INTERFACE ${OpenMP_CXX_FLAGS})
target_link_libraries(mwb_openmp INTERFACE
  "$<${_is_executable}:${MWB_LIBGOMP_STATIC}>"
  "$<$<NOT:${_is_executable}>:OpenMP::OpenMP_CXX>"
  Threads::Threads ${CMAKE_DL_LIBS})
add_link_options(-static-libstdc++ -static-libgcc -Wl,--exclude-libs,ALL)
