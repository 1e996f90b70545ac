# nlohmann/json for the Windows cross build: the header-only library from Debian's
# nlohmann-json3-dev. Its own package file would put /usr/include, with glibc's headers, on the
# cross compiler's include path, so only the nlohmann/ folder is offered, through a link in the
# build folder.
set(nlohmann_json_VERSION 3)
set(_mwb_json_include ${CMAKE_BINARY_DIR}/nlohmann-json-include)
if(NOT EXISTS ${_mwb_json_include}/nlohmann/json.hpp)
  file(MAKE_DIRECTORY ${_mwb_json_include})
  file(CREATE_LINK /usr/include/nlohmann ${_mwb_json_include}/nlohmann SYMBOLIC)
endif()
if(NOT TARGET nlohmann_json::nlohmann_json)
  add_library(nlohmann_json::nlohmann_json INTERFACE IMPORTED)
  set_target_properties(nlohmann_json::nlohmann_json PROPERTIES INTERFACE_INCLUDE_DIRECTORIES ${_mwb_json_include})
endif()
